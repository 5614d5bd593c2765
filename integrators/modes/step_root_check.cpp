// SPDX-License-Identifier: Apache-2.0
#include "modes/step_root_check.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::internal {

bool StepRootCheck::RootsAt(const Eigen::MatrixXd& taylor, double t_n, int q, double t,
                            double* g) {
  node_x_ = taylor.col(q);
  for (int k = q - 1; k >= 0; --k) node_x_ = taylor.col(k) + (t - t_n) * node_x_;
  if (!system_.Solve(t, node_x_)) return false;
  system_.Roots(t, node_x_, g);
  return true;
}

double StepRootCheck::FirstViolation(const Eigen::MatrixXd& taylor, double t_n, double h, int q,
                                     const Eigen::VectorXd& g_start,
                                     const Eigen::VectorXd& g_end, double rtol, double atol) {
  rtol_ = rtol;
  atol_ = atol;
  system_.RootFloors(0, root_floors_);
  slack_applied_ = false;
  piece_middles_.resize(kMaxPieceDepth);
  // An LCS mode here (G_u singular at the split: no affine map) has root
  // functions of x's degree, which its interpolant reproduces. A nonlinear
  // one's are resolved by halving pieces rather than by degree: 2 or 3, so
  // that a step that needs no halving costs 2–3 solves.
  const StepInterpolant& interpolant = StepInterpolant::OfDegree(
      system_.affine() ? std::min(q, kMaxInterpolantDegree) : std::clamp(q, 2, 3));
  return PieceViolation(taylor, t_n, h, q, interpolant, -1, 0, g_start, g_end, 0);
}

// The piece [t_n + h s_start, t_n + h s_end] of the step, whose ends' root
// values are g_start and g_end: the root functions at the interpolant's
// interior nodes and its extra node, and the polynomials through them
// bounded over the piece (StepInterpolant::Bound), so a dip between the
// nodes is found as well as one at them. A dip counts once the root
// functions themselves confirm it at its lowest point; a piece too long for
// the degree to tell (the error estimate reaches the floor, or a dip is not
// confirmed) is halved, kMaxPieceDepth times at most: a root function
// driven by t (F's own time dependence) varies on scales the steps of x
// need not resolve.
double StepRootCheck::PieceViolation(const Eigen::MatrixXd& taylor, double t_n, double h, int q,
                                     const StepInterpolant& interpolant, double s_start,
                                     double s_end, const Eigen::VectorXd& g_start,
                                     const Eigen::VectorXd& g_end, int depth) {
  const double t_end = t_n + h * s_end, width = h * (s_end - s_start);
  const int degree = interpolant.degree();
  const int m2 = 2 * system_.m();
  Eigen::MatrixXd& values = piece_values_;
  values.resize(m2, degree + 1);
  values.col(0) = g_start;
  values.col(degree) = g_end;
  for (int i = 1; i < degree; ++i) {
    const double t = t_end + width * interpolant.node(i);
    if (!RootsAt(taylor, t_n, q, t, values.col(i).data())) return t;
  }
  // An LCS's root functions have x's degree: its interpolant is exact.
  Eigen::VectorXd& extra = piece_extra_;
  extra.resize(system_.affine() ? 0 : m2);
  const double t_extra = t_end + width * interpolant.extra_node();
  if (extra.size() > 0 && !RootsAt(taylor, t_n, q, t_extra, extra.data())) return t_extra;
  PieceBound bound = interpolant.Bound(values, extra, root_floors_, t_end, width);
  if ((!std::isnan(bound.dip) || bound.uncertain) && !slack_applied_) {
    // A bound row's F may be off by what the state's error moves it
    // (Holds): that slack costs F's Jacobians, so only a piece that dips
    // pays it.
    node_x_ = taylor.col(0);
    const double state_error = rtol_ * node_x_.lpNorm<Eigen::Infinity>() + atol_;
    f_slack_ = system_.FSlack(t_n, node_x_, state_error);
    system_.RootFloors(f_slack_, root_floors_);
    slack_applied_ = true;
    bound = interpolant.Bound(values, extra, root_floors_, t_end, width);
  }
  if (!std::isnan(bound.dip)) {
    extra.resize(m2);
    if (!RootsAt(taylor, t_n, q, bound.dip, extra.data())) return bound.dip;
    if (system_.FirstViolation(Eigen::VectorXd::Constant(1, bound.dip), node_x_, system_.u(),
                               f_slack_) >= 0)
      return bound.dip;
    bound.uncertain = true;
  }
  if (!bound.uncertain || depth == kMaxPieceDepth) return NAN;
  const double s_middle = (s_start + s_end) / 2, t_middle = t_n + h * s_middle;
  // The middle's values outlive the left half's check (the right half
  // starts there): one kept vector per depth, all sized in FirstViolation
  // (a resize here would move those the callers' g_start and g_end are).
  Eigen::VectorXd& g_middle = piece_middles_[static_cast<std::size_t>(depth)];
  g_middle.resize(m2);
  if (!RootsAt(taylor, t_n, q, t_middle, g_middle.data())) return t_middle;
  const double left = PieceViolation(taylor, t_n, h, q, interpolant, s_start, s_middle, g_start,
                                     g_middle, depth + 1);
  if (!std::isnan(left)) return left;
  return PieceViolation(taylor, t_n, h, q, interpolant, s_middle, s_end, g_middle, g_end,
                        depth + 1);
}

}  // namespace dvi::internal
