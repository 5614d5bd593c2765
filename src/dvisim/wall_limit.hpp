// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

namespace dvi::dvisim {

/// `--max-wall SECONDS` / `method.max_wall`: ends the process when a run
/// takes longer than its wall-clock budget, with `message` on standard error
/// and exit code 1. A SIGALRM handler writes the message and calls _exit, so
/// it ends a run wherever it is (a factorization, a solver, an integrator
/// loop alike) without cooperation from the library; files are written only
/// after the run, with the limit disarmed, so none is left half-written.
class WallClockLimit {
 public:
  WallClockLimit() = default;
  /// Disarms.
  ~WallClockLimit();
  WallClockLimit(const WallClockLimit&) = delete;
  WallClockLimit& operator=(const WallClockLimit&) = delete;

  /// (Re)starts the budget: `seconds` from now (> 0), then `message`.
  void Arm(double seconds, const std::string& message);
  void Disarm();

 private:
  bool armed_ = false;
};

}  // namespace dvi::dvisim
