// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/trajectory.hpp"

namespace dvi {

/// One member's result as the ensemble returns it on rank 0.
struct EnsembleResult {
  std::size_t member = 0;  ///< Its index in 0 … count − 1.
  IntegrationStatus status = IntegrationStatus::kSuccess;
  /// The integrator's message; for a member that threw (bad input, a
  /// problem the integrator refused), `refused` is set and this is what().
  std::string message;
  bool refused = false;
  double t_final = 0;        ///< Time of the last sample (0 when none).
  Eigen::VectorXd x_final;   ///< State there (empty when no sample).
  std::size_t events = 0;
  IntegrationStats stats;    ///< stats.wall_seconds: the member's own time.
  bool certified = false;    ///< The certificate was evaluated and holds.
  /// options.reduce(trajectory), when given (also for failed members: the
  /// function sees their partial trajectory).
  std::vector<double> reduction;
  /// The whole trajectory when options.keep_trajectories: its samples,
  /// events, intervals, statistics and certificate. Dense output stays on
  /// the rank that integrated it: StateAt between samples is not available
  /// on a gathered trajectory.
  std::optional<Trajectory> trajectory;
  bool succeeded() const { return !refused && status == IntegrationStatus::kSuccess; }
};

struct EnsembleOptions {
  /// Gather every member's whole trajectory to rank 0 (memory: all of
  /// them at once there). Off: only the scalars above and the reduction.
  bool keep_trajectories = false;
  /// A user function of a member's trajectory (e.g. a final-state norm,
  /// an event count in a window), evaluated on the member's rank so that
  /// only its values travel.
  std::function<std::vector<double>(const Trajectory&)> reduce;
};

/// Where this process sits in the ensemble: rank 0 of 1 without MPI (or
/// when MPI is not initialized), else its rank in MPI_COMM_WORLD.
struct EnsembleRank {
  int rank = 0;
  int size = 1;
};
EnsembleRank CurrentEnsembleRank();

/// Whether this build of dvi distributes ensembles over MPI ranks.
bool EnsembleUsesMpi();

/// MPI for a program whose only MPI use is RunEnsemble (dvisim sweep):
/// initializes it when this build has MPI and the process was started by
/// mpiexec/mpirun (an Open MPI, PMI or PMIx launch environment), so that a
/// program started by hand does not pay MPI's start-up; finalizes it when
/// destroyed. A program that calls MPI_Init itself needs none.
class EnsembleMpiSession {
 public:
  EnsembleMpiSession(int* argc, char*** argv);
  ~EnsembleMpiSession();
  EnsembleMpiSession(const EnsembleMpiSession&) = delete;
  EnsembleMpiSession& operator=(const EnsembleMpiSession&) = delete;

 private:
  bool started_ = false;
};

/// Integrates members 0 … count − 1, member i by one serial call of
/// `member(i)`, and returns their results in member order.
///
/// Distribution: with MPI built in and initialized (the caller owns
/// MPI_Init/MPI_Finalize), member i runs on rank i mod size (cyclic: a
/// sweep's neighbours, which cost alike, land on different ranks), every
/// rank must call this with the same count and options, and rank 0 gathers
/// and returns all results (other ranks return an empty vector). Without
/// MPI it runs every member here. Each member's numbers do not depend on
/// the rank count: a member is integrated by the same serial code wherever
/// it runs, and results travel bit for bit.
///
/// A member that throws (dvi::Error or std::exception) is a result with
/// refused = true and the message; it never ends the ensemble.
std::vector<EnsembleResult> RunEnsemble(std::size_t count,
                                        const std::function<Trajectory(std::size_t)>& member,
                                        const EnsembleOptions& options = {});

}  // namespace dvi
