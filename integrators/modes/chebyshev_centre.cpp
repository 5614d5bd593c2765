// SPDX-License-Identifier: Apache-2.0
#include "modes/chebyshev_centre.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace dvi::internal {
namespace {

// A tableau entry below this, relative to the largest of its column, is
// zero: no pivot on it.
constexpr double kPivotTolerance = 1e-12;

}  // namespace

bool ChebyshevCentre(const Eigen::MatrixXd& S, const Eigen::VectorXd& g, Eigen::VectorXd& s,
                     double& radius) {
  const Eigen::Index rows = S.rows(), k = S.cols();
  const Eigen::VectorXd norms = S.rowwise().norm();
  // s = s⁺ − s⁻ with s± ≥ 0, and r = ρ − shift with ρ ≥ 0, the shift so
  // large that the right-hand sides b = g + ‖S_i‖·shift are ≥ 0: the
  // origin (s = 0, ρ = 0) with every slack basic is then a vertex to start
  // from. Columns: s⁺ (k), s⁻ (k), ρ, the slacks (rows); the last, b.
  double shift = 0;
  for (Eigen::Index i = 0; i < rows; ++i) shift = std::max(shift, -g(i) / norms(i));
  const Eigen::Index variables = 2 * k + 1, columns = variables + rows;
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(rows, columns + 1);
  T.leftCols(k) = -S;
  T.middleCols(k, k) = S;
  T.col(2 * k) = norms;
  T.middleCols(variables, rows).setIdentity();
  T.col(columns) = (g + shift * norms).cwiseMax(0.0);
  // The reduced costs of the objective ρ (maximized): only ρ's at the start.
  Eigen::RowVectorXd cost = Eigen::RowVectorXd::Zero(columns + 1);
  cost(2 * k) = 1;
  std::vector<Eigen::Index> basis(rows);
  for (Eigen::Index i = 0; i < rows; ++i) basis[i] = variables + i;
  // Bland's rule ends in at most C(columns, rows) pivots; this cap only
  // guards against round-off that would break its argument.
  const long max_pivots = 50 * static_cast<long>(columns);
  for (long pivot = 0;; ++pivot) {
    if (pivot == max_pivots) return false;
    const double cost_scale =
        kPivotTolerance * std::max(1.0, cost.head(columns).cwiseAbs().maxCoeff());
    Eigen::Index entering = -1;
    for (Eigen::Index j = 0; j < columns && entering < 0; ++j)
      if (cost(j) > cost_scale) entering = j;
    if (entering < 0) break;  // optimal
    const double column_scale =
        kPivotTolerance * std::max(1.0, T.col(entering).cwiseAbs().maxCoeff());
    Eigen::Index leaving = -1;
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < rows; ++i) {
      if (T(i, entering) <= column_scale) continue;
      const double ratio = T(i, columns) / T(i, entering);
      if (ratio < best || (ratio == best && basis[i] < basis[leaving])) {
        best = ratio;
        leaving = i;
      }
    }
    if (leaving < 0) return false;  // unbounded
    T.row(leaving) /= T(leaving, entering);
    for (Eigen::Index i = 0; i < rows; ++i)
      if (i != leaving && T(i, entering) != 0) T.row(i) -= T(i, entering) * T.row(leaving);
    cost -= cost(entering) * T.row(leaving);
    basis[leaving] = entering;
  }
  Eigen::VectorXd y = Eigen::VectorXd::Zero(variables);
  for (Eigen::Index i = 0; i < rows; ++i)
    if (basis[i] < variables) y(basis[i]) = T(i, columns);
  s = y.head(k) - y.segment(k, k);
  radius = y(2 * k) - shift;
  return true;
}

}  // namespace dvi::internal
