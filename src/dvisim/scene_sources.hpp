// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "dvi/lcs.hpp"

namespace dvi::dvisim {

/// Time-dependent sources of scenes (docs/scenes.md): an lcs scene's p or q
/// with expressions in t, and the breakpoints any scene with sources may
/// declare.

/// Named constants of a scene's "params".
using SceneParams = std::vector<std::pair<std::string, double>>;

/// A vector field of an lcs scene (p or q): numbers, or expressions in t and
/// the params. All numbers: `constant` holds them, `source` stays empty.
/// Else `source` evaluates every entry at t (numbers as constants), `rate`
/// its exact d/dt, and `constant` is zero.
/// @throws InputError naming the entry ("problem.q[2]: unknown symbol
/// \"x1\" ...": sources depend on t only).
void ReadSourceVector(const nlohmann::json& value, const std::string& path, int size,
                      const SceneParams& params, const std::string& params_path,
                      Eigen::VectorXd& constant, TimeSource& source, TimeSource* rate);

/// "breakpoints": an array of times (numbers or expressions in the params),
/// strictly ascending within (0, horizon], or {"period": T, "offset": t1}
/// for the times t1 + k·T (k = 0, 1, …; offset 0 by default) that lie in
/// (0, horizon] (one at the horizon makes the last row the left limit).
/// @throws InputError naming the entry: not finite, not after the one
/// before, outside (0, horizon], a period that is not
/// positive, or more than kMaxBreakpoints times.
std::vector<double> ReadBreakpoints(const nlohmann::json& value, const std::string& path,
                                    const SceneParams& params, const std::string& params_path,
                                    double horizon);

/// More breakpoints than this in one scene are refused (a period far below
/// the horizon, a unit mistake): each is a stop and a restart.
inline constexpr long kMaxBreakpoints = 1'000'000;

}  // namespace dvi::dvisim
