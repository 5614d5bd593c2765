// SPDX-License-Identifier: Apache-2.0
#include "study_runs.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <functional>
#include <limits>
#include <type_traits>
#include <variant>

#include <Eigen/Eigenvalues>

#include "dvi/error.hpp"
#include "run_command.hpp"

namespace dvi::dvisim {
namespace {

using Clock = std::chrono::steady_clock;

// A dense eigenvalue problem costs n³: beyond this many states ρ is not
// computed (a second for n = 1000 on this machine would be longer than most
// studies' runs).
constexpr Eigen::Index kMaxStiffnessStates = 400;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The scene as `dvisim run` would integrate it with the run's method and
// parameter; event and auto keep every step's interpolant.
Scene SceneOfRun(const Scene& scene, const PlannedRun& run,
                 const std::vector<double>& output_times) {
  Scene copy = scene;
  copy.output.samples = 0;
  copy.output.times.clear();
  switch (run.method) {
    case StudyMethod::kSteppingTheta0:
    case StudyMethod::kSteppingHalf:
    case StudyMethod::kSteppingTheta1:
      copy.method = IntegrationMethod::kTimeStepping;
      copy.stepping.h = run.parameter;
      // A fixed h: what the convergence results of Sect. 7 are about.
      copy.stepping.adaptive = false;
      copy.stepping.theta = run.method == StudyMethod::kSteppingTheta0 ? 0.0
                            : run.method == StudyMethod::kSteppingHalf ? 0.5
                                                                       : 1.0;
      copy.stepping.gamma = run.method == StudyMethod::kSteppingHalf ? 0.5 : 1.0;
      copy.output.times = output_times;
      break;
    default:
      copy.method = run.method == StudyMethod::kAuto ? IntegrationMethod::kAuto
                                                     : IntegrationMethod::kEventDriven;
      copy.event.rtol = run.parameter;
      copy.event.atol = run.atol;
      copy.event.dense_output = DenseOutputPolicy::kAlways;
      copy.stepping.dense_output = DenseOutputPolicy::kAlways;
      break;
  }
  return copy;
}

// The time of `run` to the horizon, sampled nowhere on the way: the study's
// grid is where it measures errors, not work a user asked for (sampling
// 20 000 points cost plain CVODE 40 times its integration on bench's decay).
RunTiming TimeToHorizon(const std::function<void()>& run, int repeats) {
  const Clock::time_point start = Clock::now();
  run();
  return TimeRepeated(run, SecondsSince(start), repeats);
}

ExecutedRun RunIntegrator(const Scene& scene, const PlannedRun& run,
                          const std::vector<double>& output_times, int repeats) {
  ExecutedRun executed;
  const Scene copy = SceneOfRun(scene, run, output_times);
  try {
    if (IsAdaptive(run.method)) {
      // Event and auto sample nowhere (their dense output answers later):
      // the answer's run is the first timing sample.
      const Clock::time_point start = Clock::now();
      executed.trajectory = IntegrateScene(copy);
      const double first = SecondsSince(start);
      executed.timed_steps = executed.trajectory.stats.steps;
      executed.timing = TimeRepeated([&] { IntegrateScene(copy); }, first, repeats);
    } else {
      executed.trajectory = IntegrateScene(copy);
      const Scene timed = SceneOfRun(scene, run, {scene.horizon});
      executed.timing =
          TimeToHorizon([&] { executed.timed_steps = IntegrateScene(timed).stats.steps; }, repeats);
    }
  } catch (const InputError& error) {
    executed.message = error.what();
    return executed;
  } catch (const InvalidInputError& error) {
    executed.message = error.what();
    return executed;
  }
  executed.status = std::string(ToString(executed.trajectory.status));
  executed.message = executed.trajectory.message;
  executed.stats = executed.trajectory.stats;
  return executed;
}

baselines::BaselineRun RunBaseline(StudyMethod method, const baselines::BaselineProblem& problem,
                                   double rtol, double atol) {
  if (method == StudyMethod::kCvode) return baselines::RunPlainCvode(problem, rtol, atol);
  if (method == StudyMethod::kDopri5) return baselines::RunOdeintDopri5(problem, rtol, atol);
  return baselines::RunOdeintRosenbrock4(problem, rtol, atol);
}

ExecutedRun RunBaselineMethod(const Scene& scene, const PlannedRun& run,
                              const std::vector<double>& output_times, int repeats) {
  ExecutedRun executed;
  std::optional<baselines::BaselineProblem> problem = AsBaselineProblem(scene);
  if (!problem) {
    executed.message = "the implicit RHS (5.2) needs a VI in u";
    return executed;
  }
  try {
    baselines::BaselineProblem timed = *problem;
    // odeint starts at the first output time, and CVODE's first step
    // depends on the first after t0: both as in the measured run.
    timed.output_times = {problem->t0};
    const auto first = std::upper_bound(output_times.begin(), output_times.end(), problem->t0);
    if (first != output_times.end() && *first < problem->t_end)
      timed.output_times.push_back(*first);
    timed.output_times.push_back(problem->t_end);
    executed.timing = TimeToHorizon(
        [&] {
          executed.timed_steps = RunBaseline(run.method, timed, run.parameter, run.atol).steps;
        },
        repeats);
    problem->output_times = output_times;
    baselines::BaselineRun result = RunBaseline(run.method, *problem, run.parameter, run.atol);
    executed.stats.rhs_evals = result.rhs_evals;
    executed.stats.steps = result.steps;
    if (!result.failure.empty() || result.states.size() != output_times.size()) {
      executed.status = "failed";
      executed.message = result.failure;
      return executed;
    }
    executed.status = "success";
    executed.baseline_states = std::move(result.states);
  } catch (const InvalidInputError& error) {
    executed.message = error.what();
  }
  return executed;
}

}  // namespace

ExecutedRun ExecuteRun(const Scene& scene, const PlannedRun& run,
                       const std::vector<double>& output_times, int repeats) {
  if (!run.refused.empty()) {
    ExecutedRun refused;
    refused.message = run.refused;
    return refused;
  }
  return IsImplicitRhsBaseline(run.method) ? RunBaselineMethod(scene, run, output_times, repeats)
                                           : RunIntegrator(scene, run, output_times, repeats);
}

std::optional<baselines::BaselineProblem> AsBaselineProblem(const Scene& scene) {
  baselines::BaselineProblem problem;
  problem.x0 = scene.x0;
  problem.t0 = 0;
  problem.t_end = scene.horizon;
  problem.max_steps = scene.event.max_steps;  // method.max_steps, as event-driven integration
  const bool has_vi = std::visit(
      [&](const auto& p) {
        using Problem = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<Problem, Lcs> || std::is_same_v<Problem, Dvi>) {
          problem.dvi = p;
          return true;
        } else if constexpr (std::is_same_v<Problem, FilippovSystem>) {
          problem.dvi = p.ToSeparable().ToDvi();
          return true;
        } else {
          return false;
        }
      },
      scene.problem);
  if (!has_vi) return std::nullopt;
  return problem;
}

double StiffnessAtStart(const Scene& scene, const Eigen::VectorXd& u0) {
  const Eigen::MatrixXd J = std::visit(
      [&](const auto& p) -> Eigen::MatrixXd {
        using Problem = std::decay_t<decltype(p)>;
        const int n = scene.n;
        if constexpr (std::is_same_v<Problem, Lcs>) {
          if (p.A.rows() > kMaxStiffnessStates) return Eigen::MatrixXd();
          return Eigen::MatrixXd(p.A);
        } else if constexpr (std::is_same_v<Problem, Dvi>) {
          Eigen::MatrixXd Jx = Eigen::MatrixXd::Zero(n, n), Ju = Eigen::MatrixXd::Zero(n, p.m);
          if (!p.f_jacobian || u0.size() != p.m) return Eigen::MatrixXd();
          p.f_jacobian(0, scene.x0, u0, Jx, Ju);
          return Jx;
        } else if constexpr (std::is_same_v<Problem, FilippovSystem>) {
          Eigen::MatrixXd Jx = Eigen::MatrixXd::Zero(n, n);
          if (!p.f0_jacobian) return Eigen::MatrixXd();
          p.f0_jacobian(0, scene.x0, Jx);
          return Jx;
        } else if constexpr (std::is_same_v<Problem, ProjectedDynamics>) {
          // x' = −F(x) − ν: the Jacobian of the smooth part is −∂F/∂x.
          Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
          if (!p.F_jacobian) return Eigen::MatrixXd();
          p.F_jacobian(0, scene.x0, J);
          return -J;
        } else {
          return Eigen::MatrixXd();
        }
      },
      scene.problem);
  if (J.size() == 0 || J.rows() > kMaxStiffnessStates || !J.allFinite())
    return std::numeric_limits<double>::quiet_NaN();
  return J.eigenvalues().cwiseAbs().maxCoeff();
}

}  // namespace dvi::dvisim
