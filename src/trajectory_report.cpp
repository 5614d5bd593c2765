// SPDX-License-Identifier: Apache-2.0
// Trajectory::Report: the run in words, in the spirit of Ceres'
// Solver::Summary::BriefReport / FullReport.
#include <map>
#include <sstream>
#include <string>

#include "dvi/trajectory.hpp"

namespace dvi {
namespace {

// "VI 0.012 (≤ 1)" or "VI not measured".
std::string Measure(const char* name, const CertifiedMeasure& measure) {
  std::ostringstream out;
  out << name;
  if (measure.checked == 0) {
    out << " not measured";
    return out.str();
  }
  out << " ratio " << measure.ratio << " (value " << measure.value << ", bound " << measure.bound
      << ", at t = " << measure.time << ", component " << measure.component << ", "
      << measure.checked << " points)";
  return out.str();
}

std::string CertificateWord(const Certificate& certificate) {
  if (!certificate.evaluated) return "not evaluated";
  return certificate.certified() ? "certified" : "NOT certified";
}

}  // namespace

std::string Trajectory::Report(ReportDetail detail) const {
  std::ostringstream out;
  const double t0 = times.empty() ? 0 : times.front();
  if (detail == ReportDetail::kBrief) {
    out << status << ": t = [" << t0 << ", " << final_time() << "], " << stats.steps
        << " steps, " << events.size() << " events, " << CertificateWord(certificate) << ", "
        << stats.wall_seconds << " s";
    return out.str();
  }
  out << "Status: " << status << "\n";
  if (!message.empty()) out << "Message: " << message << "\n";
  out << "Span: t = [" << t0 << ", " << final_time() << "], " << times.size() << " samples, n = "
      << state_dim() << ", m = " << multiplier_dim() << "\n";
  out << "Methods:\n";
  if (intervals.empty()) out << "  none recorded\n";
  for (const MethodInterval& interval : intervals)
    out << "  [" << interval.from << ", " << interval.to << "] " << interval.method << ": "
        << interval.reason << "\n";
  out << "Steps: " << stats.steps << " accepted, " << stats.rejected_steps << " rejected\n";
  out << "Evaluations: " << stats.rhs_evals << " right-hand side, " << stats.jacobian_evals
      << " Jacobian\n";
  out << "VI solves: " << stats.vi_solves << ", " << stats.solver_iterations
      << " solver iterations, largest residual " << stats.max_residual << "\n";
  std::map<EventKind, long> by_kind;
  for (const Event& event : events) ++by_kind[event.kind];
  out << "Events: " << events.size();
  const char* separator = " (";
  for (const auto& [kind, count] : by_kind) {
    out << separator << kind << " " << count;
    separator = ", ";
  }
  out << (by_kind.empty() ? "" : ")") << "\n";
  for (const Event& event : events)
    if (event.kind == EventKind::kJump)
      out << "  state jump at t = " << event.time << ": x⁺ = x⁻ + B η, impulse η = ("
          << event.impulse.transpose() << ")\n";
  if (stats.reduced_modes > 0)
    out << "Reduced modes (Theorems 5.2/5.3): " << stats.reduced_modes
        << ", largest constraint drift " << stats.max_constraint_drift << "\n";
  out << "Certificate: " << CertificateWord(certificate) << "\n";
  if (certificate.evaluated) {
    out << "  " << Measure("VI", certificate.vi) << "\n";
    out << "  " << Measure("ODE", certificate.ode) << "\n";
    if (!certificate.basis.empty()) out << "  " << certificate.basis << "\n";
  }
  out << "Wall time: " << stats.wall_seconds << " s\n";
  return out.str();
}

}  // namespace dvi
