// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstddef>
#include <utility>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"
#include "dvi/mode.hpp"

namespace dvi::internal {

/// An LCS mode's split rows (BoxModeSystem::SplitRows): the free rows
/// G = c + C x + M u of the active set, G_u's LU, and u_α = map_offset +
/// map x. All of it is a function of the mode alone (the LCS is fixed, u off
/// the free set is at its bounds), so a mode left and entered again needs
/// none of it formed anew.
struct LcsModeSplit {
  Eigen::VectorXd c;  // G = c + C x + M u, a rows
  SparseMatrix C;
  Eigen::MatrixXd M;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of G_u
  // u_α = map_offset + map x when the mode is small (map empty otherwise);
  // by rows, as BoxModeSystem::SolveLcsMode reads it.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> map;
  Eigen::VectorXd map_offset;
  bool regular = false;  // G_u nonsingular

  /// Exchanges the contents without copying them (Eigen 3.4's SparseMatrix
  /// has no move operations).
  void swap(LcsModeSplit& other) {
    c.swap(other.c);
    C.swap(other.C);
    M.swap(other.M);
    std::swap(lu, other.lu);
    map.swap(other.map);
    map_offset.swap(other.map_offset);
    std::swap(regular, other.regular);
  }
};

/// The splits of the last kLcsModeSplits modes left, the least recently
/// stored giving way to a new one: a circuit that switches among a few
/// modes (the diode bridge alternates between two, and the smoothness test
/// of a switch, smooth_switch.hpp, re-enters the mode just left) splits
/// each of them once (issue 31, "cheaper events"). Only unreduced modes with a dense map are kept: their
/// split is small (a × n ≤ the map's bound) and a reduced one depends on
/// the passes that selected it.
class LcsModeSplits {
 public:
  static constexpr std::size_t kLcsModeSplits = 4;

  /// The kept split of mode, or null; its key is cleared (the caller
  /// swaps it out, leaving the slot free).
  LcsModeSplit* Take(const Mode& mode) {
    if (mode.empty()) return nullptr;
    for (Kept& kept : kept_)
      if (kept.mode == mode) {
        kept.mode.clear();
        return &kept.split;
      }
    return nullptr;
  }
  /// The slot to keep mode's split in (the caller swaps it in): a free
  /// one, else the least recently stored.
  LcsModeSplit& Slot(const Mode& mode) {
    Kept* slot = &kept_[0];
    for (Kept& kept : kept_) {
      if (kept.mode.empty()) {
        slot = &kept;
        break;
      }
      if (kept.stored < slot->stored) slot = &kept;
    }
    slot->stored = ++clock_;
    slot->mode = mode;
    return slot->split;
  }

 private:
  struct Kept {
    Mode mode;  // empty: a free slot
    long stored = 0;  // when it was stored (clock_)
    LcsModeSplit split;
  };
  std::array<Kept, kLcsModeSplits> kept_;
  long clock_ = 0;
};

}  // namespace dvi::internal
