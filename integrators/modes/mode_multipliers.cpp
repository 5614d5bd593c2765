// SPDX-License-Identifier: Apache-2.0
#include "modes/mode_multipliers.hpp"

#include <algorithm>
#include <utility>

#include "modes/box_mode.hpp"

namespace dvi::internal {

ModeMultipliers::ModeMultipliers(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                                 const SolverOptions& solver, bool affine, const Lcs* lcs)
    : dvi_(dvi),
      lower_(std::move(lower)),
      upper_(std::move(upper)),
      solver_(solver),
      affine_(affine) {
  if (lcs) lcs_ = *lcs;
}

void ModeMultipliers::Append(double begin, double end, const Mode& mode,
                             const Eigen::VectorXd& u) {
  if (modes_.empty() || modes_.back() != mode) modes_.push_back(mode);
  if (pieces_.empty()) u_size_ = u.size();
  pieces_.push_back({begin, end, modes_.size() - 1, u_values_.size()});
  u_values_.insert(u_values_.end(), u.data(), u.data() + u.size());
}

bool ModeMultipliers::Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const {
  // The first piece ending at or after t; its start must reach back to t.
  const auto piece = std::lower_bound(pieces_.begin(), pieces_.end(), t,
                                      [](const Piece& p, double time) { return p.end < time; });
  if (piece == pieces_.end() || t < piece->begin) return false;
  BoxModeSystem system(dvi_, lower_, upper_, solver_, affine_, lcs_ ? &*lcs_ : nullptr);
  system.Enter(modes_[piece->mode],
               Eigen::Map<const Eigen::VectorXd>(u_values_.data() + piece->u, u_size_));
  if (!system.Solve(t, x)) return false;
  u = system.u();
  return true;
}

}  // namespace dvi::internal
