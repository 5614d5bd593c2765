// SPDX-License-Identifier: Apache-2.0
// The exchange of a build without MPI: one rank, nothing travels.
#include "rank_exchange.hpp"

namespace dvi {

bool EnsembleUsesMpi() { return false; }

EnsembleMpiSession::EnsembleMpiSession(int*, char***) {}
EnsembleMpiSession::~EnsembleMpiSession() = default;

namespace internal {

EnsembleRank RankInWorld() { return {}; }

std::string GatherToRankZero(const std::string& local) { return local; }

}  // namespace internal
}  // namespace dvi
