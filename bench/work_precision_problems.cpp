// SPDX-License-Identifier: Apache-2.0
#include "work_precision_problems.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "dvi/event_driven.hpp"
#include "support/convergence.hpp"
#include "support/forced_box_dvi.hpp"
#include "support/rectifier.hpp"
#include "support/reference_dvis.hpp"

namespace dvi::bench {
namespace {

// x' = u, u ∈ SOL([−1, 1], u + x), x0 = 3: u = clamp(−x), so x = 3 − t
// (u at its lower bound −1) until x = 1 at t = 2, then x = e^{2−t} (u free).
WorkPrecisionProblem SaturatedDecay(int output_count) {
  WorkPrecisionProblem problem;
  problem.name = "decay";
  problem.title = "x' = u, u in SOL([-1,1], u + x), x0 = 3, [0, 5]";
  problem.reference = "exact";
  problem.dvi = testing::SaturatedDecay();
  problem.x0 = Eigen::VectorXd::Constant(1, 3);
  problem.t_end = 5;
  problem.output_times = testing::Linspace(0, 5, output_count);
  for (const double t : problem.output_times)
    problem.exact.push_back(testing::SaturatedDecayExact(t));
  problem.schedule = {{0, 2, {MultiplierBound::kLower}}, {2, 5, {MultiplierBound::kFree}}};
  return problem;
}

// RC circuit with an ideal diode in series with Rd (C = R = I = 1, Rd = ½):
// v' = −v − 1 + u, 0 ≤ u ⊥ v + Rd u ≥ 0, D = Rd > 0 a P-matrix (Sect. 5.1).
// From v0 = 2 the diode is off until v = 0 at t* = ln 3, then u = −v/Rd and
// v relaxes to v∞ = −1/3 with τ = 1/3.
WorkPrecisionProblem DiodeCircuit(int output_count) {
  WorkPrecisionProblem problem;
  problem.name = "diode";
  problem.title = "RC circuit, ideal diode + Rd (LCS, D = 0.5), v0 = 2, [0, 3]";
  problem.reference = "exact";
  Eigen::MatrixXd A(1, 1), B(1, 1), C(1, 1), D(1, 1);
  A << -1;
  B << 1;
  C << 1;
  D << 0.5;
  problem.lcs =
      Lcs::Dense(A, B, C, D, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Zero(1));
  problem.dvi = problem.lcs->ToDvi();
  problem.x0 = Eigen::VectorXd::Constant(1, 2);
  problem.t_end = 3;
  problem.output_times = testing::Linspace(0, 3, output_count);
  const double switch_time = std::log(3.0), v_inf = -1.0 / 3, tau = 1.0 / 3;
  for (const double t : problem.output_times)
    problem.exact.push_back(Eigen::VectorXd::Constant(
        1, t <= switch_time ? -1 + 3 * std::exp(-t)
                            : v_inf - v_inf * std::exp(-(t - switch_time) / tau)));
  problem.schedule = {{0, switch_time, {MultiplierBound::kLower}},
                      {switch_time, 3, {MultiplierBound::kFree}}};
  return problem;
}

// testing::BallSpiral: u = Π_B(x) on the unit disc through the VI's KKT
// system in z = (u, μ); the constraint is active (μ free) until it is
// released at t = 2 (μ at its bound 0).
WorkPrecisionProblem BallSpiral(int output_count) {
  WorkPrecisionProblem problem;
  problem.name = "ball";
  problem.title = "x' = [[0,-1],[1,0]]x - u, u in SOL(unit disc, u - x), x0 = (3, 0), [0, 5]";
  problem.reference = "exact";
  problem.dvi = testing::BallSpiral();
  problem.x0 = Eigen::Vector2d(3, 0);
  problem.t_end = 5;
  problem.output_times = testing::Linspace(0, 5, output_count);
  for (const double t : problem.output_times) problem.exact.push_back(testing::BallSpiralExact(t));
  constexpr MultiplierBound kFree = MultiplierBound::kFree;
  problem.schedule = {{0, 2, {kFree, kFree, kFree}},
                      {2, 5, {kFree, kFree, MultiplierBound::kLower}}};
  return problem;
}

// problem.exact and problem.schedule from an event run at rtol = 1e-13 (for
// problems without a closed form), with its distance to an rtol = 1e-12 run
// as the reference's error estimate.
void ReferenceFromEventRun(WorkPrecisionProblem& problem) {
  EventDrivenOptions options;
  options.rtol = 1e-13;
  options.atol = 1e-15;
  options.output_times = problem.output_times;
  const Trajectory reference =
      IntegrateEventDriven(problem.dvi, problem.x0, problem.t0, problem.t_end, options);
  options.rtol *= 10;
  options.atol *= 10;
  const Trajectory check =
      IntegrateEventDriven(problem.dvi, problem.x0, problem.t0, problem.t_end, options);
  if (!reference.succeeded() || !check.succeeded())
    throw std::runtime_error(problem.name + " reference run failed: " + reference.message +
                             check.message);
  double distance = 0;
  for (const double t : problem.output_times) {
    problem.exact.push_back(reference.StateAt(t));
    distance = std::max(
        distance, (check.StateAt(t) - problem.exact.back()).lpNorm<Eigen::Infinity>());
  }
  std::ostringstream reference_text;
  reference_text << "event run, rtol = 1e-13, atol = 1e-15 (max distance to the rtol = 1e-12 run: "
                 << distance << ")";
  problem.reference = reference_text.str();

  // The mode the VI selects at t0, then each event moves one component;
  // simultaneous events share a segment start.
  IndexOneRhs rhs(problem.dvi);
  if (!rhs.SelectMode(problem.t0, problem.x0))
    throw std::runtime_error(problem.name + ": no mode at t0: " + rhs.message());
  ModeSegment segment{problem.t0, problem.t_end, rhs.mode()};
  for (const Event& event : reference.events) {
    if (event.time > segment.from) {
      segment.to = event.time;
      problem.schedule.push_back(segment);
      segment.from = event.time;
    }
    segment.mode[event.index] = event.kind == EventKind::kReachedLower   ? MultiplierBound::kLower
                                : event.kind == EventKind::kReachedUpper ? MultiplierBound::kUpper
                                                                         : MultiplierBound::kFree;
  }
  segment.to = problem.t_end;
  problem.schedule.push_back(segment);
}

// testing::SaturatedOscillator, 15 kinks, against a tight event run.
WorkPrecisionProblem SaturatedOscillator(int output_count) {
  WorkPrecisionProblem problem;
  problem.name = "oscillator";
  problem.title = "nonlinear strongly monotone 3-D box DVI, x0 = (2.5, 0, 1), [0, 10]";
  problem.dvi = testing::SaturatedOscillator();
  problem.x0 = Eigen::Vector3d(2.5, 0, 1);
  problem.t_end = 10;
  problem.output_times = testing::Linspace(0, 10, output_count);
  ReferenceFromEventRun(problem);
  return problem;
}

// Half-wave rectifier: a sine source charges C through an ideal diode in
// series with Rd (R = C = 1, Rd = ½), v' = −v + u, 0 ≤ u ⊥ u/2 + v − sin ωt
// ≥ 0. 100 periods over [0, 20]: the diode switches 200 times, so here a
// kink's cost to a method without events is paid 200 times over.
WorkPrecisionProblem HalfWaveRectifier(int output_count) {
  constexpr double kPeriods = 100, kEnd = 20, kRd = 0.5;
  constexpr double kOmega = 2 * 3.14159265358979323846 * kPeriods / kEnd;
  WorkPrecisionProblem problem;
  problem.name = "rectifier";
  problem.title = "half-wave rectifier v' = -v + u, 0 <= u _|_ u/2 + v - sin(10 pi t) >= 0, "
                  "v0 = 1, [0, 20] (100 periods)";
  problem.dvi.n = 1;
  problem.dvi.m = 1;
  problem.dvi.K = ConvexSet::Orthant(1);
  problem.dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     Eigen::VectorXd& out) { out.resize(1); out << -x(0) + u(0); };
  problem.dvi.F = [](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     Eigen::VectorXd& out) {
    out.resize(1);
    out << kRd * u(0) + x(0) - std::sin(kOmega * t);
  };
  problem.x0 = Eigen::VectorXd::Constant(1, 1);
  problem.t_end = kEnd;
  problem.output_times = testing::Linspace(0, kEnd, output_count);
  ReferenceFromEventRun(problem);
  return problem;
}

// Issue 27's rectifier, nondimensional (RC = ω = Vs = 1): an ideal diode
// (D = 0) clamps v to the source while it conducts, a reduced (index-two)
// mode whose constraint moves with time, 5 periods. The implicit right-hand
// side of the baselines and the oracle needs ∂F/∂u nonsingular, which the
// clamp is not: only event-driven and time-stepping integrate it.
WorkPrecisionProblem ClampedRectifier(int output_count) {
  constexpr testing::Rectifier kCircuit{1, 1, 1, 1};
  constexpr double kEnd = 10 * 3.14159265358979323846;
  WorkPrecisionProblem problem;
  problem.name = "clamp";
  problem.title = "v' = u - v, 0 <= u _|_ v - sin t >= 0 (index two), v0 = 0, [0, 10 pi]";
  problem.reference = "exact";
  problem.dvi = testing::RectifierDvi(kCircuit, true);
  problem.x0 = Eigen::VectorXd::Zero(1);
  problem.t_end = kEnd;
  problem.output_times = testing::Linspace(0, kEnd, output_count);
  const testing::RectifierSwitches switches = testing::RectifierExactSwitches(kCircuit, kEnd);
  for (const double t : problem.output_times)
    problem.exact.push_back(
        Eigen::VectorXd::Constant(1, testing::RectifierExactV(kCircuit, switches, t)));
  double from = 0;
  for (std::size_t k = 0; k < switches.off.size(); ++k) {
    problem.schedule.push_back({from, switches.off[k], {MultiplierBound::kFree}});
    from = k < switches.on.size() ? switches.on[k] : kEnd;
    problem.schedule.push_back({switches.off[k], from, {MultiplierBound::kLower}});
  }
  if (from < kEnd) problem.schedule.push_back({from, kEnd, {MultiplierBound::kFree}});
  return problem;
}

// testing::ForcedBoxDvi with a = 3: 13 kinks over [0, 20] driven by F's
// time dependence, against its exact piecewise solution.
WorkPrecisionProblem ForcedBox(int output_count) {
  constexpr double kForcing = 3, kEnd = 20;
  WorkPrecisionProblem problem;
  problem.name = "forced";
  problem.title = "x' = u, u in SOL([-1,1], u + x - 3 sin t), x0 = 0, [0, 20]";
  problem.reference = "exact";
  problem.dvi = testing::ForcedBoxDvi(kForcing);
  problem.x0 = Eigen::VectorXd::Zero(1);
  problem.t_end = kEnd;
  problem.output_times = testing::Linspace(0, kEnd, output_count);
  const std::vector<testing::ForcedBoxPiece> pieces = testing::ForcedBoxExact(kForcing, kEnd);
  for (const double t : problem.output_times)
    problem.exact.push_back(Eigen::VectorXd::Constant(1, testing::ForcedBoxX(kForcing, pieces, t)));
  for (std::size_t k = 0; k < pieces.size(); ++k)
    problem.schedule.push_back({pieces[k].from, k + 1 < pieces.size() ? pieces[k + 1].from : kEnd,
                                {pieces[k].mode > 0   ? MultiplierBound::kUpper
                                 : pieces[k].mode < 0 ? MultiplierBound::kLower
                                                      : MultiplierBound::kFree}});
  return problem;
}

}  // namespace

std::vector<WorkPrecisionProblem> MakeWorkPrecisionProblems(int output_count) {
  std::vector<WorkPrecisionProblem> problems;
  problems.push_back(SaturatedDecay(output_count));
  problems.push_back(DiodeCircuit(output_count));
  problems.push_back(SaturatedOscillator(output_count));
  problems.push_back(BallSpiral(output_count));
  problems.push_back(HalfWaveRectifier(output_count));
  problems.push_back(ClampedRectifier(output_count));
  problems.push_back(ForcedBox(output_count));
  return problems;
}

double MaxError(const WorkPrecisionProblem& problem, const std::vector<Eigen::VectorXd>& states) {
  if (states.size() != problem.exact.size()) return std::numeric_limits<double>::infinity();
  double error = 0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    const double difference = (states[k] - problem.exact[k]).lpNorm<Eigen::Infinity>();
    if (!std::isfinite(difference)) return std::numeric_limits<double>::infinity();
    error = std::max(error, difference);
  }
  return error;
}

}  // namespace dvi::bench
