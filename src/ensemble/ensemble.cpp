// SPDX-License-Identifier: Apache-2.0
#include "dvi/ensemble.hpp"

#include <algorithm>
#include <chrono>
#include <exception>

#include "rank_exchange.hpp"
#include "result_codec.hpp"

namespace dvi {
namespace {

EnsembleResult RunMember(std::size_t index, const std::function<Trajectory(std::size_t)>& member,
                         const EnsembleOptions& options) {
  EnsembleResult result;
  result.member = index;
  try {
    Trajectory trajectory = member(index);
    result.status = trajectory.status;
    result.message = trajectory.message;
    if (!trajectory.times.empty()) {
      result.t_final = trajectory.times.back();
      result.x_final = trajectory.states.back();
    }
    result.events = trajectory.events.size();
    result.stats = trajectory.stats;
    result.certified = trajectory.certificate.evaluated && trajectory.certificate.certified();
    if (options.reduce) result.reduction = options.reduce(trajectory);
    if (options.keep_trajectories) result.trajectory = std::move(trajectory);
  } catch (const std::exception& error) {
    result.refused = true;
    result.message = error.what();
  }
  return result;
}

}  // namespace

EnsembleRank CurrentEnsembleRank() { return internal::RankInWorld(); }

std::vector<EnsembleResult> RunEnsemble(std::size_t count,
                                        const std::function<Trajectory(std::size_t)>& member,
                                        const EnsembleOptions& options) {
  const EnsembleRank where = internal::RankInWorld();
  // Every result goes through the byte form, on one rank too: what a
  // caller gets never depends on the rank count (a gathered trajectory has
  // no dense output, so neither has a local one).
  std::string bytes;
  for (std::size_t i = static_cast<std::size_t>(where.rank); i < count;
       i += static_cast<std::size_t>(where.size))
    internal::AppendResult(RunMember(i, member, options), bytes);
  std::vector<EnsembleResult> results = internal::ReadResults(internal::GatherToRankZero(bytes));
  std::sort(results.begin(), results.end(),
            [](const EnsembleResult& a, const EnsembleResult& b) { return a.member < b.member; });
  return results;
}

}  // namespace dvi
