// SPDX-License-Identifier: Apache-2.0
#include "study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "mode_sequence.hpp"
#include "parallel_jobs.hpp"
#include "study_reference.hpp"
#include "study_runs.hpp"

namespace dvi::dvisim {
namespace {

// The step ladder around the scene's own h: 64h … h/8, the coarse half the
// stability probes, the fine half where the orders show.
constexpr int kCoarsestFactor = 6;
constexpr int kFinestFactor = -3;

std::vector<double> RtolLadder(const Scene& scene) {
  if (!scene.study.rtol.empty()) return scene.study.rtol;
  return std::vector<double>(std::begin(kDefaultRtols), std::end(kDefaultRtols));
}

std::vector<double> StepLadder(const Scene& scene) {
  if (!scene.study.h.empty()) return scene.study.h;
  std::vector<double> ladder;
  for (int k = kCoarsestFactor; k >= kFinestFactor; --k) {
    const double h = std::ldexp(scene.stepping.h, k);
    if (h > scene.horizon / kMinSteps) continue;
    CheckStepCount(h, scene.horizon, scene.stepping.max_steps,
                   "the default step ladder (method.h·2^k, k = 6 … −3; give study.h)");
    ladder.push_back(h);
  }
  return ladder;
}

std::vector<StudyMethod> Methods(const Scene& scene) {
  if (scene.study.methods.empty())
    return std::vector<StudyMethod>(std::begin(kAllStudyMethods), std::end(kAllStudyMethods));
  std::vector<StudyMethod> methods;
  for (const StudyMethod method : kAllStudyMethods)  // the table's order
    if (std::count(scene.study.methods.begin(), scene.study.methods.end(), method) > 0)
      methods.push_back(method);
  return methods;
}

// Event and auto come first: the reference, the evaluation times and the
// baselines' applicability follow from them.
bool InFirstPhase(StudyMethod method) {
  return method == StudyMethod::kEvent || method == StudyMethod::kAuto;
}

std::vector<PlannedRun> Plan(const Scene& scene) {
  const double atol_per_rtol = scene.event.atol / scene.event.rtol;
  std::vector<PlannedRun> plan;
  for (const StudyMethod method : Methods(scene)) {
    std::string refused;
    if (method == StudyMethod::kEvent) {
      if (const std::string why = WhyNotEventDriven(scene); !why.empty())
        refused = "event-driven integration does not apply: " + why;
    }
    if (IsImplicitRhsBaseline(method) && !AsBaselineProblem(scene))
      refused = "the implicit RHS (5.2) needs u ∈ SOL(K, F(t, x, ·)); a " + scene.type +
                " scene has no such VI";
    if (IsAdaptive(method)) {
      for (const double rtol : RtolLadder(scene))
        plan.push_back({method, rtol, rtol * atol_per_rtol, refused});
    } else {
      for (const double h : StepLadder(scene)) plan.push_back({method, h, 0, refused});
    }
  }
  return plan;
}

// Where the baselines' implicit RHS does not apply: a mode that
// event-driven integration reduced by differentiation is of index two.
std::string IndexTwoRefusal(const std::vector<PlannedRun>& plan,
                            const std::vector<ExecutedRun>& executed) {
  for (std::size_t k = 0; k < plan.size(); ++k) {
    const long reduced = executed[k].stats.reduced_modes;
    if (reduced > 0)
      return "index two or more: " + ToString(plan[k].method) +
             " at rtol = " + ShortNumber(plan[k].parameter) + " chose " + std::to_string(reduced) +
             " mode(s) by the differentiation procedure (Theorems 5.2/5.3), where u(t, x) is "
             "not the Lipschitz function of the state the implicit RHS (5.2) needs";
  }
  return "";
}

// Fills outcome, errors, switches and mode comparison of a run that reached
// the horizon (or says why it did not).
void Measure(const PlannedRun& planned, const ExecutedRun& executed, const EvaluationTimes& times,
             const Reference& reference, double horizon, StudyRun& run) {
  run.status = executed.status;
  if (executed.status == "refused") {
    run.outcome = RunOutcome::kRefused;
    run.reason = executed.message;
    return;
  }
  if (!executed.succeeded()) {
    run.outcome = RunOutcome::kFailed;
    run.reason = executed.status + ": " + executed.message;
    return;
  }
  run.grid_error = MaxDistance(ValuesAt(executed, times, times.grid), reference.grid);
  run.switch_error =
      MaxDistance(ValuesAt(executed, times, times.switch_points), reference.switch_points);
  run.max_error = std::max(run.grid_error, run.switch_error);
  const ReferenceReport& report = reference.report;
  if (!(run.max_error <= report.scale)) {
    run.outcome = RunOutcome::kFailed;
    run.reason = "diverged: max error " + ShortNumber(run.max_error) +
                 " above the solution's size " + ShortNumber(report.scale);
    return;
  }
  run.outcome = RunOutcome::kConverged;
  if (IsImplicitRhsBaseline(planned.method)) return;  // no events located
  const double window = IsAdaptive(planned.method) ? kAdaptiveSwitchWindow * horizon
                                                   : kSteppingSwitchWindow * planned.parameter;
  const std::vector<Switch> switches = GroupSwitches(executed.trajectory.events, window);
  run.switches = static_cast<int>(switches.size());
  if (!report.modes_known) {
    run.mode_sequence = "n/a";
    return;
  }
  if (!SameModeSequence(switches, reference.switches)) {
    run.mode_sequence = "differs";
    run.outcome = RunOutcome::kWrongModes;
    run.reason = std::to_string(switches.size()) + " switches against the reference's " +
                 std::to_string(reference.switches.size()) +
                 (switches.size() == reference.switches.size() ? ", other events at some" : "");
    return;
  }
  run.mode_sequence = "same";
  run.event_time_error = SwitchTimeError(switches, reference.switches);
}

// The fitted rungs: neighbours on the ladder, the finest whose error is
// above `floor` and that converged; a rung between that is not breaks the
// run of neighbours (an order read across it would mix regimes).
std::vector<const StudyRun*> FittedRungs(const std::vector<StudyRun>& runs, StudyMethod method,
                                         double floor) {
  std::vector<const StudyRun*> ladder;  // coarse (or loose) to fine (or tight)
  for (const StudyRun& run : runs)
    if (run.method == method) ladder.push_back(&run);
  const auto fits = [floor](const StudyRun* run) {
    return run->outcome == RunOutcome::kConverged && run->max_error > floor;
  };
  auto finest = ladder.rbegin();
  while (finest != ladder.rend() && !fits(*finest)) ++finest;
  std::vector<const StudyRun*> fitted;
  for (auto run = finest;
       run != ladder.rend() && fits(*run) && fitted.size() < static_cast<std::size_t>(kFitRungs);
       ++run)
    fitted.insert(fitted.begin(), *run);
  return fitted;
}

std::vector<Slope> FitSlopes(const std::vector<StudyRun>& runs, double floor,
                             double stepping_floor) {
  std::vector<Slope> slopes;
  for (const StudyMethod method : kAllStudyMethods) {
    if (std::none_of(runs.begin(), runs.end(),
                     [method](const StudyRun& run) { return run.method == method; }))
      continue;
    const std::vector<const StudyRun*> fitted =
        FittedRungs(runs, method, IsAdaptive(method) ? floor : stepping_floor);
    Slope slope;
    slope.method = method;
    slope.rungs = static_cast<int>(fitted.size());
    if (fitted.size() >= 3) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (const StudyRun* run : fitted) {
        const double x = std::log10(run->parameter), y = std::log10(run->max_error);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
      }
      const double count = static_cast<double>(fitted.size());
      slope.slope = (count * sxy - sx * sy) / (count * sxx - sx * sx);
      slope.decades = std::log10(fitted.front()->parameter / fitted.back()->parameter);
    }
    slopes.push_back(slope);
  }
  return slopes;
}

}  // namespace

std::string ToString(RunOutcome outcome) {
  switch (outcome) {
    case RunOutcome::kConverged:
      return "converged";
    case RunOutcome::kWrongModes:
      return "wrong mode sequence";
    case RunOutcome::kRefused:
      return "refused";
    case RunOutcome::kFailed:
      return "failed";
  }
  return "?";
}

StudyResult RunStudy(const Scene& scene, const StudyOptions& options) {
  if (scene.x0.size() != scene.n)
    throw InputError("study: the scene is not an initial-value problem (it gives no x0)");
  std::vector<PlannedRun> plan = Plan(scene);
  const int total = static_cast<int>(plan.size());
  int done = 0;
  const auto progress = [&] {
    ++done;
    if (options.progress) options.progress(done, total);
  };
  std::vector<std::size_t> first, second;
  for (std::size_t k = 0; k < plan.size(); ++k)
    (InFirstPhase(plan[k].method) ? first : second).push_back(k);
  std::vector<ExecutedRun> executed(plan.size());
  const auto run_phase = [&](const std::vector<std::size_t>& indices,
                             const std::vector<double>& output_times) {
    RunJobs(
        indices.size(), options.jobs,
        [&](std::size_t j) {
          executed[indices[j]] = ExecuteRun(scene, plan[indices[j]], output_times, options.repeats);
        },
        progress);
  };
  run_phase(first, {});

  // The reference of the first phase (exact, or the tightest event / auto
  // run), the evaluation times around its switches, then the other methods
  // sampled there.
  FirstReference first_reference = ChooseFirstReference(scene, plan, executed);
  const EvaluationTimes times =
      MakeEvaluationTimes(scene, first_reference.switch_times, StepLadder(scene));
  const std::string index_two = IndexTwoRefusal(plan, executed);
  for (const std::size_t k : second)
    if (IsImplicitRhsBaseline(plan[k].method) && plan[k].refused.empty() && !index_two.empty())
      plan[k].refused = index_two;
  run_phase(second, times.output);

  // An auto reference that stepped (over a Zeno interval) is as accurate
  // there as the scene's h, which its rtol does not refine: the same run at
  // h/2 estimates that error.
  std::optional<ExecutedRun> halved;
  if (first_reference.run && !first_reference.modes_known) {
    Scene finer = scene;
    finer.stepping.h /= 2;
    halved = ExecuteRun(finer, plan[*first_reference.run], {}, 1);
  }
  const Reference reference =
      CompleteReference(scene, plan, executed, first_reference, times, halved);
  StudyResult result;
  result.title = scene.name.empty() ? scene.type : scene.name;
  result.reference = reference.report;
  result.grid_points = static_cast<int>(times.grid.size());
  for (std::size_t k = 0; k < plan.size(); ++k) {
    StudyRun run;
    run.method = plan[k].method;
    run.parameter = plan[k].parameter;
    run.atol = plan[k].atol;
    const ExecutedRun& e = executed[k];
    Measure(plan[k], e, times, reference, scene.horizon, run);
    run.steps = e.stats.steps;
    run.rejected_steps = e.stats.rejected_steps;
    run.rhs_evals = e.stats.rhs_evals;
    run.vi_solves = e.stats.vi_solves;
    const Certificate& certificate = e.trajectory.certificate;
    run.certificate_evaluated = certificate.evaluated;
    if (certificate.evaluated) {
      run.certified = certificate.certified();
      run.vi_ratio = certificate.vi.ratio;
      run.ode_ratio = certificate.ode.ratio;
    }
    run.timing = e.timing;
    result.runs.push_back(run);
  }
  const double estimate = reference.report.error_estimate;
  result.error_floor = reference.report.kind == "exact" || !std::isfinite(estimate)
                           ? kRoundOff * reference.report.scale
                           : std::max(10 * estimate, kRoundOff * reference.report.scale);
  result.stepping_error_floor =
      std::max(result.error_floor,
               kSolverLevel * std::max(1.0, scene.horizon) * scene.stepping.solver.tolerance);
  result.slopes = FitSlopes(result.runs, result.error_floor, result.stepping_error_floor);
  result.stiffness = StiffnessAtStart(scene, reference.u0);
  result.measured_times = times.grid;
  result.measured_times.insert(result.measured_times.end(), times.switch_points.begin(),
                               times.switch_points.end());
  result.reference_values = reference.grid;
  result.reference_values.insert(result.reference_values.end(), reference.switch_points.begin(),
                                 reference.switch_points.end());
  return result;
}

}  // namespace dvi::dvisim
