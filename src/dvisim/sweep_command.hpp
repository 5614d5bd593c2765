// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>
#include <ostream>
#include <string>

namespace dvi::dvisim {

/// `dvisim sweep SWEEP.json [--out DIR] [--trajectories]` (docs/sweeps.md).
struct SweepCommand {
  std::string sweep_path;
  std::optional<std::string> out_dir;  ///< Overrides output.dir.
  bool trajectories = false;           ///< Also write each member's files.
};

/// Integrates every member of the sweep (dvi::RunEnsemble: split over MPI
/// ranks when started by mpiexec in a build with MPI, else on this
/// process) and writes, on rank 0 only, a new folder: sweep.csv (one row
/// per member: its overrides, status, message, final time and state,
/// events, statistics, certificate, wall time) and, when asked,
/// members/<k>/trajectory.csv and summary.json. A member that fails or is
/// refused is a row with its status and message; the sweep goes on.
/// Returns 0 when the sweep ran (whatever its members did), 2 for a bad
/// sweep file or --out (nothing written), 1 when the outputs could not be
/// written. Other ranks print nothing and return the same code.
int RunSweepCommand(const SweepCommand& command, std::ostream& out, std::ostream& err);

}  // namespace dvi::dvisim
