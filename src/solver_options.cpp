// SPDX-License-Identifier: Apache-2.0
#include "dvi/solver_options.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "check.hpp"

namespace dvi {
namespace {

constexpr std::array<std::pair<SolverMethod, std::string_view>, 6> kMethodNames = {{
    {SolverMethod::kAuto, "auto"},
    {SolverMethod::kLemke, "lemke"},
    {SolverMethod::kPgs, "pgs"},
    {SolverMethod::kNewton, "newton"},
    {SolverMethod::kExtragradient, "extragradient"},
    {SolverMethod::kKkt, "kkt"},
}};

}  // namespace

std::string_view ToString(SolverMethod method) {
  for (const auto& [value, name] : kMethodNames) {
    if (value == method) return name;
  }
  return "auto";
}

SolverMethod ParseSolverMethod(std::string_view name) {
  for (const auto& [value, word] : kMethodNames) {
    if (word == name) return value;
  }
  DVI_THROW_UNLESS(false,
                   "unknown solver method \""
                       << std::string(name)
                       << "\"; expected one of auto, lemke, pgs, newton, extragradient, kkt");
  return SolverMethod::kAuto;
}

void SolverOptions::Validate() const {
  DVI_THROW_UNLESS(std::any_of(kMethodNames.begin(), kMethodNames.end(),
                               [this](const auto& entry) { return entry.first == method; }),
                   "SolverOptions::method = " << static_cast<int>(method)
                                              << " is not a SolverMethod");
  // Written as positive conditions so that NaN fails them.
  DVI_THROW_UNLESS(tolerance > 0.0 && tolerance < 1.0,
                   "SolverOptions::tolerance = " << tolerance << " is outside (0, 1)");
  DVI_THROW_UNLESS(max_iterations >= 0,
                   "SolverOptions::max_iterations = " << max_iterations << " is negative");
  DVI_THROW_UNLESS(sparse_ordering == SparseOrdering::kAmd ||
                       sparse_ordering == SparseOrdering::kGiven,
                   "SolverOptions::sparse_ordering = " << static_cast<int>(sparse_ordering)
                                                       << " is not a SparseOrdering");
  DVI_THROW_UNLESS(watchdog_steps >= 0,
                   "SolverOptions::watchdog_steps = " << watchdog_steps << " is negative");
  DVI_THROW_UNLESS(pgs_relaxation > 0.0 && pgs_relaxation < 2.0,
                   "SolverOptions::pgs_relaxation = " << pgs_relaxation << " is outside (0, 2)");
}

std::string_view ToString(SparseOrdering ordering) {
  switch (ordering) {
    case SparseOrdering::kAmd: return "amd";
    case SparseOrdering::kGiven: return "given";
  }
  return "unknown";
}

}  // namespace dvi
