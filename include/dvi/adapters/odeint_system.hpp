// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

#include "dvi/adapters/index_one_rhs.hpp"

namespace dvi {

/// Boost.Odeint adapters for an IndexOneRhs (no Boost include needed here):
/// any odeint stepper integrates an index-one DVI as the ODE (5.2),
///   integrate_times(make_controlled<runge_kutta_dopri5<std::vector<double>>>(
///       1e-8, 1e-8), OdeintSystem(rhs), x, times.begin(), times.end(), dt, observer);
///   integrate_const(make_dense_output<rosenbrock4<double>>(1e-8, 1e-8),
///       std::make_pair(OdeintSystem(rhs), OdeintJacobian(rhs)), x, ...);
/// State is any container with size() and operator[] (std::vector<double>,
/// boost::numeric::ublas::vector<double>); Matrix has operator()(i, j)
/// (ublas::matrix<double>). Both arrive sized, as odeint passes them.
///
/// No events: odeint has no root finding, so a step that crosses a mode
/// change of u steps across a kink of the right-hand side; error control
/// still converges, at the cost of rejected steps and reduced order there.
/// IntegrateEventDriven (event_driven.hpp) stops at the kinks instead.
///
/// Both adapters hold a reference to the IndexOneRhs, which must outlive
/// them, and share its mode and warm start. Failure to compute u throws
/// std::runtime_error with IndexOneRhs::message(): odeint has no error codes.

class OdeintSystem {
 public:
  explicit OdeintSystem(IndexOneRhs& rhs) : rhs_(&rhs) {}

  template <class State, class Deriv>
  void operator()(const State& x, Deriv& dxdt, double t) const {
    Eigen::VectorXd x_eigen(static_cast<Eigen::Index>(x.size())), xdot;
    for (std::size_t i = 0; i < x.size(); ++i) x_eigen(static_cast<Eigen::Index>(i)) = x[i];
    if (!rhs_->Evaluate(t, x_eigen, xdot)) throw std::runtime_error(rhs_->message());
    for (std::size_t i = 0; i < x.size(); ++i) dxdt[i] = xdot(static_cast<Eigen::Index>(i));
  }

 private:
  IndexOneRhs* rhs_;
};

/// The Jacobian for odeint's rosenbrock4: J = ∂/∂x of (5.2) in the current
/// mode (IndexOneRhs::Jacobian), dfdt = ∂/∂t by a forward difference with
/// step h = √ε·max(1, |t|): its truncation error O(h·|f_tt|) and round-off
/// O(ε·|f|/h) balance there, leaving ~√ε ≈ 1.5e-8 relative error — far below
/// what the W-method's order conditions need from an approximate f_t. The
/// difference sees a kink when t + h crosses a mode change, which is then
/// as wrong as any one-sided derivative there. Costs two evaluations.
class OdeintJacobian {
 public:
  explicit OdeintJacobian(IndexOneRhs& rhs) : rhs_(&rhs) {}

  template <class State, class Matrix>
  void operator()(const State& x, Matrix& J, double t, State& dfdt) const {
    const auto n = static_cast<Eigen::Index>(x.size());
    Eigen::VectorXd x_eigen(n), f_ahead, f_here;
    for (Eigen::Index i = 0; i < n; ++i) x_eigen(i) = x[static_cast<std::size_t>(i)];
    const double t_ahead =
        t + std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(t));
    const double h = t_ahead - t;  // the step actually represented
    // t + h first, so that the mode and multiplier left behind are those at t.
    Eigen::MatrixXd J_eigen;
    if (!rhs_->Evaluate(t_ahead, x_eigen, f_ahead) || !rhs_->Jacobian(t, x_eigen, J_eigen) ||
        !rhs_->Evaluate(t, x_eigen, f_here))
      throw std::runtime_error(rhs_->message());
    for (Eigen::Index i = 0; i < n; ++i) {
      dfdt[static_cast<std::size_t>(i)] = (f_ahead(i) - f_here(i)) / h;
      for (Eigen::Index k = 0; k < n; ++k)
        J(static_cast<std::size_t>(i), static_cast<std::size_t>(k)) = J_eigen(i, k);
    }
  }

 private:
  IndexOneRhs* rhs_;
};

}  // namespace dvi
