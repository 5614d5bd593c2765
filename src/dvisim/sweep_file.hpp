// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace dvi::dvisim {

/// Owns: reading a sweep file (docs/sweeps.md): a base scene and the
/// overrides that make each member. The members are the product of the
/// `members` list (default: one empty entry) and the `grid` (each key a
/// JSON pointer into the scene, each value a list; the first key varies
/// slowest), in that order.
struct Sweep {
  nlohmann::json base;               ///< The base scene's JSON.
  std::string base_source;           ///< "sweep.scene" or the scene file's path.
  std::vector<std::string> columns;  ///< Every overridden pointer, in file order.
  /// Per member, (pointer, value) in application order: its members entry,
  /// then its grid point.
  std::vector<std::vector<std::pair<std::string, nlohmann::json>>> members;
  std::string out_dir;               ///< output.dir, default "out/sweep".
  bool trajectories = false;         ///< output.trajectories.
};

/// The most members a sweep may have: far beyond any study on one machine,
/// and a bound that keeps a typo (a grid of 10⁹ points) from filling memory.
inline constexpr std::size_t kMaxSweepMembers = 1000000;

/// Parses a sweep file's text; `path` locates a scene given by file name
/// (relative to the sweep file's folder). @throws InputError naming the
/// field ("sweep.grid[\"/x0/3\"]: ...").
Sweep ParseSweep(const std::string& text, const std::string& path);

/// The member's scene: the base with its overrides applied. A pointer may
/// replace any existing value and add a key to an existing object, never
/// create a missing parent or an array entry. @throws InputError naming
/// the member and the pointer.
nlohmann::json MemberScene(const Sweep& sweep, std::size_t member);

}  // namespace dvi::dvisim
