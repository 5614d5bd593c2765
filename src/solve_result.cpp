// SPDX-License-Identifier: Apache-2.0
#include "dvi/solve_result.hpp"

namespace dvi {

std::string_view ToString(SolveStatus status) {
  switch (status) {
    case SolveStatus::kSolved:
      return "solved";
    case SolveStatus::kInfeasible:
      return "infeasible";
    case SolveStatus::kMaxIterations:
      return "max-iterations";
    case SolveStatus::kFailed:
      return "failed";
  }
  return "failed";
}

}  // namespace dvi
