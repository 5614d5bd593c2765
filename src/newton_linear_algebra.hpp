// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi::internal {

/// The linear algebra of SolveNewton's iteration on a problem whose
/// Jacobian J has a structure the caller knows better than a general sparse
/// factorization does (a boundary-value VI's per-step blocks). Every matrix
/// is H = diag(Da) + diag(Db) J for row scalings given per call; the
/// contract of each member is that of SolveNewton's dense and KLU paths.
class NewtonLinearAlgebra {
 public:
  virtual ~NewtonLinearAlgebra() = default;
  /// Evaluates (or checks) J at z; false if J has a non-finite entry.
  virtual bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd& f) = 0;
  /// scale += |J| |z|.
  virtual void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const = 0;
  /// gradient = Da∘Φ + Jᵀ(Db∘Φ); scratch is a vector of the problem's size.
  virtual void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                        const Eigen::VectorXd& phi, Eigen::VectorXd& scratch,
                        Eigen::VectorXd& gradient) const = 0;
  /// x = H⁻¹ rhs; false when H is (numerically) singular.
  virtual bool FactorAndSolve(const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                              const Eigen::VectorXd& rhs, Eigen::VectorXd& x) = 0;
  /// The natural-map step: on entry d holds the steps of the active
  /// components to their bounds, zeros elsewhere; solves (J_FF + shift·I)
  /// d_F = −F_F − J_FA d_A. False when that matrix is (numerically) singular.
  virtual bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                               double shift, Eigen::VectorXd& d) = 0;
  /// x = −(HᵀH + μI)⁻¹ ∇Ψ, the fallback where H is singular; false when the
  /// algebra has none (Newton then takes its other directions).
  virtual bool SolveRegularized(double phi_norm, const Eigen::VectorXd& da,
                                const Eigen::VectorXd& db, const Eigen::VectorXd& gradient,
                                Eigen::VectorXd& x) = 0;
};

/// SolveNewton (dvi/semismooth_newton.hpp) with the caller's linear algebra
/// in place of dense LU or KLU; mcp's Jacobian fields are not read.
SolveResult SolveNewtonWith(const BoxMcp& mcp, const SolverOptions& options,
                            Eigen::VectorXd warm_start, NewtonLinearAlgebra& algebra);

}  // namespace dvi::internal
