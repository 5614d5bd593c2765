// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "dvi/ensemble.hpp"

namespace dvi::internal {

/// Owns: the one collective an ensemble needs. Two builds of it:
/// rank_exchange_mpi.cpp (MPI_COMM_WORLD, when MPI is initialized) and
/// rank_exchange_serial.cpp (one rank).
EnsembleRank RankInWorld();

/// Every rank passes its bytes; rank 0 gets them concatenated in rank
/// order, the others an empty string. Collective: every rank must call it.
/// @throws InvalidInputError where a rank's bytes exceed what one MPI
/// message carries (2 GiB), naming the remedy.
std::string GatherToRankZero(const std::string& local);

}  // namespace dvi::internal
