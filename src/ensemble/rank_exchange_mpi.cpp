// SPDX-License-Identifier: Apache-2.0
// The exchange over MPI_COMM_WORLD: MPI_Gather of each rank's byte count,
// then MPI_Gatherv of the bytes to rank 0. MPI itself is the caller's to
// initialize; before MPI_Init (or after MPI_Finalize) this is one rank.
#include <mpi.h>

#include <climits>
#include <cstdlib>
#include <vector>

#include "check.hpp"
#include "rank_exchange.hpp"

namespace dvi {

bool EnsembleUsesMpi() { return true; }

EnsembleMpiSession::EnsembleMpiSession(int* argc, char*** argv) {
  bool launched = false;
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    launched |= std::getenv(variable) != nullptr;
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!launched || initialized != 0) return;
  int provided = 0;
  started_ = MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) == MPI_SUCCESS;
}

EnsembleMpiSession::~EnsembleMpiSession() {
  if (started_) MPI_Finalize();
}

namespace internal {
namespace {

bool MpiRunning() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized != 0 && finalized == 0;
}

}  // namespace

EnsembleRank RankInWorld() {
  EnsembleRank where;
  if (!MpiRunning()) return where;
  MPI_Comm_rank(MPI_COMM_WORLD, &where.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &where.size);
  return where;
}

std::string GatherToRankZero(const std::string& local) {
  const EnsembleRank where = RankInWorld();
  if (where.size == 1) return local;
  // Every rank learns whether any is too large before anyone throws, so
  // that no rank is left waiting in the Gatherv.
  const int too_large_here = local.size() > static_cast<std::size_t>(INT_MAX) ? 1 : 0;
  int too_large = 0;
  MPI_Allreduce(&too_large_here, &too_large, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  DVI_THROW_UNLESS(too_large == 0,
                   "ensemble: one rank's results exceed 2 GiB, more than one MPI message "
                   "carries; gather reductions instead of whole trajectories "
                   "(EnsembleOptions::keep_trajectories = false) or use more ranks");
  const int size = static_cast<int>(local.size());
  std::vector<int> sizes(where.rank == 0 ? static_cast<std::size_t>(where.size) : 0);
  MPI_Gather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(sizes.size());
  long long total = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    offsets[r] = static_cast<int>(total);
    total += sizes[r];
  }
  // The total is known on rank 0 only; it tells the others.
  int total_too_large = total > INT_MAX ? 1 : 0;
  MPI_Bcast(&total_too_large, 1, MPI_INT, 0, MPI_COMM_WORLD);
  DVI_THROW_UNLESS(total_too_large == 0,
                   "ensemble: the gathered results exceed 2 GiB, more than one MPI message "
                   "carries; gather reductions instead of whole trajectories "
                   "(EnsembleOptions::keep_trajectories = false)");
  std::string gathered(static_cast<std::size_t>(where.rank == 0 ? total : 0), '\0');
  MPI_Gatherv(local.data(), size, MPI_CHAR, gathered.data(), sizes.data(), offsets.data(),
              MPI_CHAR, 0, MPI_COMM_WORLD);
  return gathered;
}

}  // namespace internal
}  // namespace dvi
