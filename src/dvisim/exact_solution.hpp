// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

namespace dvi::dvisim {

class ExpressionTape;

/// A scene's `exact` block (docs/scenes.md): the solution x(t) in closed
/// form, one piece per mode,
///
///   "exact": {"params": {...},
///             "pieces": [{"to": T1, "x": [n expressions in t]}, ...,
///                        {"x": [...]}]}
///
/// Piece k holds on [T_k, T_{k+1}] (T_0 = 0, the last piece to the
/// horizon); its `to` is the switch time where the mode changes, a number or
/// a constant expression ("log(3)", "3*pi/4"). Pieces per mode, not one
/// expression per state, because the expression grammar has no conditional,
/// and because the switch times are what a study measures event errors
/// against. x is continuous ([Seed] (2.2): x is absolutely continuous), so
/// adjacent pieces must meet at their switch time, and the first must start
/// at x0.
class ExactSolution {
 public:
  /// Reads the block. @throws InputError naming the field: a piece whose x
  /// has other than n entries, an expression using anything but t, pi and
  /// params, switch times not increasing within (0, horizon), a last piece
  /// with a `to`, pieces that do not meet (beyond kContinuityTolerance) or
  /// a first piece that does not start at x0.
  ExactSolution(const nlohmann::json& block, const std::string& path, int n, double horizon,
                const Eigen::VectorXd& x0);

  /// Where the mode changes: the pieces' ends but the last, ascending.
  const std::vector<double>& switch_times() const { return switch_times_; }
  /// x(t) from the piece that holds t (the left one at a switch time, where
  /// both agree). Safe to call from several threads.
  Eigen::VectorXd State(double t) const;

  /// Adjacent pieces meet, and the first starts at x0, to this fraction of
  /// max(1, |x|∞): a switch time written with 10 significant digits moves x
  /// by |x'|·1e-10, far below it; a wrong formula or a typo in a switch
  /// time moves it by far more.
  static constexpr double kContinuityTolerance = 1e-8;

 private:
  std::vector<double> switch_times_;
  std::vector<std::shared_ptr<const ExpressionTape>> pieces_;
};

}  // namespace dvi::dvisim
