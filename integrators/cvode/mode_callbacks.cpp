// SPDX-License-Identifier: Apache-2.0
#include "cvode/mode_callbacks.hpp"

#include <algorithm>
#include <cmath>

#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "events/user_roots.hpp"
#include "number_text.hpp"
#include "sundials/callbacks.hpp"

namespace dvi::internal {

std::string FormatTime(double value) { return NumberText(value); }

namespace {

// A reduced mode's projection at a root evaluation that ModeRootCallback
// leaves out, relative to ‖x‖∞: 1e4 ε, the round-off of a projected step.
constexpr double kRootCorrectionRoundOff = 1e-12;

// The state as an Eigen vector; false when it or the time is not finite.
bool Load(ModeCallbackData& data, realtype t, N_Vector y) {
  const double* values = N_VGetArrayPointer(y);
  for (int i = 0; i < data.x.size(); ++i) data.x(i) = values[i];
  return std::isfinite(t) && data.x.allFinite();
}

// A callback handed a non-finite state or time. At a finite time the step
// was too long (its predictor overflowed): recoverable where CVODE allows
// it, a shorter step may do. A non-finite time means CVODE's step control
// broke down (a weighted norm overflowed, |x'|/atol beyond the largest
// double, and the step size became NaN); its retry loops, whose tests are
// all false at NaN, would never end, so the run stops with the reason.
int NonFinite(ModeCallbackData& data, realtype t, const char* callback, bool can_retry) {
  if (can_retry && std::isfinite(t)) return 1;
  data.non_finite =
      (std::isfinite(t) ? "CVODE passed a non-finite state to the " + std::string(callback) +
                              " at t = " + FormatTime(t)
                        : "CVODE passed a non-finite time to the " + std::string(callback) +
                              ": its step size broke down (x' or x overflows double "
                              "precision in its error norm at these tolerances)");
  return -1;
}

}  // namespace

// CVODE's convention: 0 success, > 0 recoverable (a smaller step may help:
// a Newton failure in the mode), < 0 fatal.
int ModeRhsCallback(realtype t, N_Vector y, N_Vector ydot, void* user_data) {
  auto& data = *static_cast<ModeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.rhs_evals;
    if (!Load(data, t, y)) return NonFinite(data, t, "right-hand side", true);
    const auto refuse = [&](const char* why) {
      ++data.refusals;
      data.refused_at = t;
      data.refused_why = why;
      return 1;
    };
    if (!data.system->Solve(t, data.x))
      return refuse("Newton on the mode's free components fails there (is F finite?)");
    data.system->Rhs(t, data.x, data.xdot);
    if (!data.xdot.allFinite()) return refuse("f is not finite there");
    std::copy(data.xdot.data(), data.xdot.data() + data.xdot.size(), N_VGetArrayPointer(ydot));
    return 0;
  });
}

int ModeDenseJacobianCallback(realtype t, N_Vector y, N_Vector, SUNMatrix Jac, void* user_data,
                          N_Vector, N_Vector, N_Vector) {
  auto& data = *static_cast<ModeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.jacobian_evals;
    if (!Load(data, t, y)) return NonFinite(data, t, "Jacobian", true);
    if (!data.system->Solve(t, data.x)) return 1;
    if (!data.system->RhsJacobian(t, data.x, data.J)) return 1;
    const long n = data.J.rows();
    for (long k = 0; k < n; ++k) {
      double* column = SUNDenseMatrix_Column(Jac, k);
      for (long i = 0; i < n; ++i) column[i] = data.J(i, k);
    }
    return 0;
  });
}

// KLU: the mode's Jacobian, formed at its entry (EnterSparseJacobian),
// copied into the compressed columns CVODE zeroed, pattern included.
int ModeSparseJacobianCallback(realtype, N_Vector, N_Vector, SUNMatrix Jac, void* user_data, N_Vector,
                           N_Vector, N_Vector) {
  auto& data = *static_cast<ModeCallbackData*>(user_data);
  ++data.jacobian_evals;
  const SparseMatrix& J = data.sparse_J;
  if (SUNSparseMatrix_NNZ(Jac) < J.nonZeros()) return -1;
  std::copy(J.outerIndexPtr(), J.outerIndexPtr() + J.cols() + 1,
            SUNSparseMatrix_IndexPointers(Jac));
  std::copy(J.innerIndexPtr(), J.innerIndexPtr() + J.nonZeros(), SUNSparseMatrix_IndexValues(Jac));
  std::copy(J.valuePtr(), J.valuePtr() + J.nonZeros(), SUNSparseMatrix_Data(Jac));
  return 0;
}

int ModeRootCallback(realtype t, N_Vector y, realtype* g, void* user_data) {
  auto& data = *static_cast<ModeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    if (!Load(data, t, y)) return NonFinite(data, t, "root functions", false);
    // A reduced mode's root functions on its constraints Φ = 0, where CVODE
    // keeps its solution (BDF: ProjectsSteps): it projects its steps' ends
    // only, and between them its interpolant is off Φ = 0 by the
    // interpolation error. Evaluated there, u of the clamp (v = sin t held
    // by a diode, u = v + cos t) reached 0 early by that error over |u̇|
    // (1.5e-5 in time at rtol 1e-3): a root return whose event, projected,
    // kept the mode, and a restart of CVODE for one step to the root's true
    // place (issue 31). A correction at the round-off of x (a projected
    // step's end) is left out: it moves no root beyond CVODE's root
    // tolerance, and a Solve at the moved point perturbs Newton's start,
    // which cost the clamp 7.5 % more RHS evaluations at rtol 1e-11 for nothing.
    if (data.project_roots && data.system->reduced()) {
      data.system->Project(t, data.x, data.root_correction, nullptr);
      if (data.root_correction.lpNorm<Eigen::Infinity>() >
          kRootCorrectionRoundOff * data.x.lpNorm<Eigen::Infinity>())
        data.x += data.root_correction;
    }
    if (!data.system->Solve(t, data.x)) return -1;
    // CVODE evaluates the root functions at every step's end: the step's
    // sample and checks solve there again (issue 31).
    data.system->KeepSolution(t, data.x);
    const int mode_roots = 2 * data.system->m();
    if (data.user_events)
      EvaluateUserRoots(*data.user_events, t, data.x, data.system->u(), g + mode_roots);
    if (mode_roots == 0) return 0;
    data.system->Roots(t, data.x, g);
    data.root_time = t;
    std::copy(g, g + mode_roots, data.roots.data());
    data.least_root = *std::min_element(g, g + mode_roots);
    data.root_undefined =
        std::any_of(g, g + mode_roots, [](double value) { return std::isnan(value); });
    return 0;
  });
}

// Keeps a reduced mode on its original constraints Φ(t, x) = 0 (Theorems
// 5.2/5.3 only make Φ̇ vanish, so Φ would drift with the integration error).
int ModeProjectionCallback(realtype t, N_Vector y, N_Vector corr, realtype, N_Vector err,
                       void* user_data) {
  auto& data = *static_cast<ModeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    if (!Load(data, t, y)) return NonFinite(data, t, "projection", true);
    Eigen::VectorXd& error = data.projected_error;
    if (err) error = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(err), data.x.size());
    data.system->Project(t, data.x, data.xdot, err ? &error : nullptr);
    std::copy(data.xdot.data(), data.xdot.data() + data.xdot.size(), N_VGetArrayPointer(corr));
    if (err) std::copy(error.data(), error.data() + error.size(), N_VGetArrayPointer(err));
    return 0;
  });
}

void ModeErrorHandler(int, const char*, const char* function, char* message, void* user_data) {
  auto& data = *static_cast<ModeCallbackData*>(user_data);
  data.cvode_message = std::string(function) + ": " + message;
}

}  // namespace dvi::internal
