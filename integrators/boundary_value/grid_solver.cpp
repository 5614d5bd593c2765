// SPDX-License-Identifier: Apache-2.0
#include "grid_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/SVD>

#include "check.hpp"
#include "dvi/semismooth_newton.hpp"
#include "grid_backend.hpp"
#include "newton_linear_algebra.hpp"
#include "output_times_check.hpp"
#include "template_algebra.hpp"
#include "template_operator.hpp"

namespace dvi::internal {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Richardson's estimate divides the last difference by 2ᵖ − 1 with the
// observed order p clamped here: a first-order method observes 1 where the
// solution is resolved, and the clamp keeps a lucky (or unlucky) ratio from
// promising an error far below (above) the difference itself.
constexpr double kMinOrder = 0.5;
constexpr double kMaxOrder = 2.0;
// M + N counts as singular below this ratio of its singular values.
constexpr double kSingularRatio = 1e-12;
// Output times closer than this fraction of the horizon are one sample, as
// for the other integrators.
constexpr double kSameTimeFraction = 1e-12;
// An output time within this fraction of h of a grid node is that node.
constexpr double kNodeFraction = 1e-9;

struct Grid {
  BoundaryValueMcp mcp;  // matrix and offset null where the template stands for them
  SolveResult result;
  long nonzeros = 0;  // of the VI's Jacobian
  bool by_backend = false;  // solved by the installed back-end (PETSc)
};

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

std::string Format(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

// x̂ᴴ of a grid at t ∈ [0, T]: linear between nodes.
Eigen::VectorXd StateAt(const Grid& grid, double t) {
  const BoundaryValueLayout& layout = grid.mcp.layout;
  const double s = std::clamp(t / grid.mcp.h, 0.0, static_cast<double>(layout.steps));
  const long i = std::min(static_cast<long>(std::floor(s)), layout.steps - 1);
  const double fraction = s - static_cast<double>(i);
  const Eigen::VectorXd& z = grid.result.z;
  return (1 - fraction) * z.segment(layout.State(i, 0), layout.n) +
         fraction * z.segment(layout.State(i + 1, 0), layout.n);
}

// The start of a finer grid from a solved coarser one: x̂ᴴ at the nodes, and
// each step's ũ from the coarse step that holds the fine step's midpoint
// (ûᴴ, the multipliers of K's lifting alike).
Eigen::VectorXd Interpolate(const Grid& coarse, const BoundaryValueLayout& fine, double fine_h) {
  Eigen::VectorXd z(fine.size());
  const BoundaryValueLayout& layout = coarse.mcp.layout;
  for (long i = 0; i <= fine.steps; ++i)
    z.segment(fine.State(i, 0), fine.n) = StateAt(coarse, static_cast<double>(i) * fine_h);
  for (long i = 1; i <= fine.steps; ++i) {
    const double middle = (static_cast<double>(i) - 0.5) * fine_h;
    const long c =
        std::min(static_cast<long>(std::floor(middle / coarse.mcp.h)), layout.steps - 1) + 1;
    z.segment(fine.Multiplier(i, 0), fine.block) =
        coarse.result.z.segment(layout.Multiplier(c, 0), layout.block);
  }
  return z;
}

class GridSolver {
 public:
  GridSolver(const AggregateProblem& problem, const BoundaryValueOptions& options)
      : problem_(problem), options_(options) {}

  // Newton on `steps` steps from `start` (empty: the projection of 0).
  Grid Solve(long steps, Eigen::VectorXd start, bool refinement) {
    const Clock::time_point begin = Clock::now();
    Grid grid;
    // PETSc's reduced-space Newton cannot leave a degenerate cold start (u
    // at its bound where F = 0, as with D = 0: its reduced system is then
    // singular, or it cycles — measured on the two-point LCS and the
    // rectifier), so a grid without a warm start (the coarsest, at most
    // coarsest_steps steps) is dvi's, on every rank alike.
    if (options_.backend == BoundaryValueBackend::kPetsc && start.size() > 0) {
      SolveOnBackend(steps, start, grid);
      Record(steps, refinement, begin, grid);
      return grid;
    }
    std::shared_ptr<const TemplateOperator> op;
    if (problem_.affine && problem_.set.r == 0) {
      op = std::make_shared<const TemplateOperator>(problem_, steps);
      grid.mcp.layout = op->layout();
      grid.mcp.horizon = problem_.horizon;
      grid.mcp.h = op->h();
      grid.mcp.affine = true;
      SetBounds(grid.mcp.layout, problem_.set, grid.mcp.mcp);
      grid.mcp.mcp.F = [op](const Eigen::VectorXd& z, Eigen::VectorXd& w) { op->Evaluate(z, w); };
      grid.nonzeros = op->nonzeros();
    } else {
      grid.mcp = Assemble(problem_, steps);
      grid.nonzeros = grid.mcp.matrix->nonZeros();
    }
    // Counted for the statistics (rhs_evals).
    VectorMap F = std::move(grid.mcp.mcp.F);
    grid.mcp.mcp.F = [F, this](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      ++rhs_evals_;
      F(z, w);
    };
    // The watchdog is for a warm start whose active set is nearly right;
    // from the cold start its relaxed steps were wasted (14 iterations
    // instead of 3 on the coarsest grid of the two-point LCS).
    SolverOptions solver = options_.solver;
    if (start.size() == 0) solver.watchdog_steps = 0;
    if (op) {
      // Time-invariant: the block solver on the step template (BlockLu).
      TemplateAlgebra algebra(op);
      grid.result = SolveNewtonWith(grid.mcp.mcp, solver, std::move(start), algebra);
    } else {
      grid.result = SolveNewton(grid.mcp.mcp, solver, std::move(start));
    }
    grid.mcp.mcp.F = std::move(F);
    // dvi's Newton evaluates (and factors) J once per iteration.
    jacobian_evals_ += grid.result.iterations;
    Record(steps, refinement, begin, grid);
    return grid;
  }

  // The grid by the installed back-end (grid_backend.hpp), which never
  // assembles dvi's matrix: the grid keeps the layout and bounds only.
  void SolveOnBackend(long steps, const Eigen::VectorXd& start, Grid& grid) {
    const GridBackendSolver& backend = PetscGridSolver();
    const int n = problem_.n;
    grid.mcp.layout = {n, problem_.set.m, problem_.set.size(), steps};
    grid.mcp.horizon = problem_.horizon;
    grid.mcp.h = problem_.horizon / static_cast<double>(steps);
    grid.mcp.affine = problem_.affine != nullptr;
    SetBounds(grid.mcp.layout, problem_.set, grid.mcp.mcp);
    // The step blocks' entries, the boundary rows counted dense.
    grid.nonzeros = steps * static_cast<long>(BuildTemplate(problem_, grid.mcp.h).matrix.nonZeros()) +
                    2L * n * n;
    SolverOptions solver = options_.solver;
    if (start.size() == 0) solver.watchdog_steps = 0;
    GridBackendResult solved = backend(problem_, steps, solver, start);
    grid.result = std::move(solved.result);
    grid.by_backend = true;
    rhs_evals_ += solved.rhs_evals;
    jacobian_evals_ += solved.jacobian_evals;
  }

  void Record(long steps, bool refinement, Clock::time_point begin, const Grid& grid) {
    BoundaryValueGrid record;
    record.steps = steps;
    record.h = grid.mcp.h;
    record.iterations = grid.result.iterations;
    record.residual = grid.result.residual;
    record.seconds = Seconds(begin);
    record.refinement = refinement;
    stats_.grids.push_back(record);
    stats_.total_iterations += grid.result.iterations;
  }

  // The warm start of a grid of `steps` steps: the solution of the grid
  // coarsening_factor times coarser (itself warm-started so), interpolated;
  // empty when the grid is coarse enough or the coarser grid failed.
  Eigen::VectorXd WarmStart(long steps) {
    const long factor = options_.coarsening_factor;
    if (factor < 2 || steps <= options_.coarsest_steps) return {};
    const long coarse_steps = (steps + factor - 1) / factor;
    const Grid coarse = Solve(coarse_steps, WarmStart(coarse_steps), false);
    if (!coarse.result.solved()) {
      failed_warm_start_ = coarse_steps;
      return {};
    }
    const BoundaryValueLayout fine{coarse.mcp.layout.n, coarse.mcp.layout.m,
                                   coarse.mcp.layout.block, steps};
    return Interpolate(coarse, fine, problem_.horizon / static_cast<double>(steps));
  }

  BoundaryValueStats& stats() { return stats_; }
  long rhs_evals() const { return rhs_evals_; }
  long jacobian_evals() const { return jacobian_evals_; }
  long failed_warm_start() const { return failed_warm_start_; }

 private:
  const AggregateProblem& problem_;
  const BoundaryValueOptions& options_;
  BoundaryValueStats stats_;
  long rhs_evals_ = 0;
  long jacobian_evals_ = 0;
  long failed_warm_start_ = 0;
};

// The mode of ũ^i read through the natural map: for each component of u
// with a bound, −1 at its lower bound, +1 at its upper, 0 between; for each
// multiplier of an inequality or a ball, 1 while its constraint is active.
void ModeOf(const Grid& grid, const LiftedSet& set, long i, std::vector<signed char>& mode) {
  const BoundaryValueLayout& layout = grid.mcp.layout;
  const Eigen::VectorXd& z = grid.result.z;
  const Eigen::VectorXd& w = grid.result.w;
  mode.assign(static_cast<std::size_t>(set.m + set.p + set.r), 0);
  for (int l = 0; l < set.m + set.p + set.r; ++l) {
    const long index = layout.Multiplier(i, l);
    const double trial = z(index) - w(index);
    signed char value = 0;
    if (l >= set.m) {
      value = trial > 0 ? 1 : 0;
    } else if (trial <= set.lower(l) && std::isfinite(set.lower(l))) {
      value = -1;
    } else if (trial >= set.upper(l) && std::isfinite(set.upper(l))) {
      value = 1;
    }
    mode[static_cast<std::size_t>(l)] = value;
  }
}

std::vector<Event> ModeChanges(const Grid& grid, const LiftedSet& set) {
  std::vector<Event> events;
  std::vector<signed char> mode, next;
  ModeOf(grid, set, 1, mode);
  for (long i = 2; i <= grid.mcp.layout.steps; ++i) {
    ModeOf(grid, set, i, next);
    const double t = static_cast<double>(i) * grid.mcp.h;
    for (std::size_t l = 0; l < next.size(); ++l) {
      if (next[l] == mode[l]) continue;
      const int index = static_cast<int>(l);
      if (index < set.m) {
        const EventKind kind = next[l] < 0   ? EventKind::kReachedLower
                               : next[l] > 0 ? EventKind::kReachedUpper
                                             : EventKind::kLeftBound;
        events.push_back({t, kind, index});
      } else {
        events.push_back({t, next[l] ? EventKind::kConstraintActive : EventKind::kConstraintReleased,
                          index - set.m});
      }
    }
    mode.swap(next);
  }
  return events;
}

// x̂ᴴ and ûᴴ at the output times, the event times, 0 and T (every node when
// no output time is asked for), each row checked against the VI when the
// problem has a certifier: a row of step i (x̂ᴴ between x^i and x^{i+1},
// u^{i+1}) may be off its VI by as far as F moves from the row to where the
// scheme solved it (AggregateProblem::vi_weight), and across the step, as
// for time-stepping (Certificate).
void Sample(const Grid& grid, const AggregateProblem& problem,
            const std::vector<double>& output_times, Trajectory& trajectory) {
  const LiftedSet& set = problem.set;
  RowCertifier* certifier = problem.certifier.get();
  const BoundaryValueLayout& layout = grid.mcp.layout;
  const double h = grid.mcp.h, horizon = grid.mcp.horizon;
  std::vector<double> times;
  if (output_times.empty()) {
    for (long i = 0; i <= layout.steps; ++i)
      times.push_back(i == layout.steps ? horizon : static_cast<double>(i) * h);
  } else {
    times = output_times;
    for (const Event& event : trajectory.events) times.push_back(event.time);
    times.push_back(0);
    times.push_back(horizon);
    std::sort(times.begin(), times.end());
    std::vector<double> merged;
    for (const double t : times)
      if (merged.empty() || t - merged.back() > kSameTimeFraction * horizon) merged.push_back(t);
    times.swap(merged);
  }
  const Eigen::VectorXd& z = grid.result.z;
  trajectory.states.reserve(times.size(), layout.n);
  trajectory.multipliers.reserve(times.size(), set.m);
  Eigen::VectorXd x_old, x_new, x_vi, x_other, u_next;
  const Eigen::VectorXd eta = problem.vi_weight.size() == layout.n
                                  ? problem.vi_weight
                                  : Eigen::VectorXd::Zero(layout.n);
  for (const double t : times) {
    const double s = t / h;
    const long node = std::lround(s);
    long step = 0;  // the row belongs to the step ending at t_step: ũ^{step} is u at t
    if (std::abs(s - static_cast<double>(node)) <= kNodeFraction) {
      trajectory.states.push_back(z.segment(layout.State(node, 0), layout.n));
      step = std::max(node, 1L);
    } else {
      const long i = std::min(static_cast<long>(std::floor(s)), layout.steps - 1);
      const double fraction = s - static_cast<double>(i);
      trajectory.states.push_back((1 - fraction) * z.segment(layout.State(i, 0), layout.n) +
                                  fraction * z.segment(layout.State(i + 1, 0), layout.n));
      step = i + 1;
    }
    trajectory.multipliers.push_back(z.segment(layout.Multiplier(step, 0), set.m));
    trajectory.times.push_back(t);
    if (!certifier) continue;
    x_old = z.segment(layout.State(step - 1, 0), layout.n);
    x_new = z.segment(layout.State(step, 0), layout.n);
    x_vi = eta.cwiseProduct(x_old) + (1 - eta.array()).matrix().cwiseProduct(x_new);
    x_other = eta.cwiseProduct(x_new) + (1 - eta.array()).matrix().cwiseProduct(x_old);
    u_next = z.segment(layout.Multiplier(step, 0), set.m);
    const double t_vi = static_cast<double>(problem.vi_at_old_time ? step - 1 : step) * h;
    const RowCertifier::Step row_step{t_vi, &x_other, &x_vi, &u_next};
    certifier->Check(t, trajectory.states.back(), trajectory.multipliers.back(),
                     {0, 0, &row_step}, trajectory.certificate.vi);
  }
}

BoundaryDiagnostics Diagnose(const BoundaryConditions& conditions, const Grid& grid) {
  BoundaryDiagnostics diagnostics;
  const BoundaryValueLayout& layout = grid.mcp.layout;
  const double horizon = grid.mcp.horizon, h = grid.mcp.h;
  const Eigen::VectorXd& z = grid.result.z;
  for (long i = 0; i < layout.steps; ++i) {
    const auto x = z.segment(layout.State(i, 0), layout.n);
    const auto next = z.segment(layout.State(i + 1, 0), layout.n);
    diagnostics.psi_observed =
        std::max(diagnostics.psi_observed, (next - x).norm() / (h * (1 + x.norm())));
  }
  const Eigen::MatrixXd sum = conditions.M + conditions.N;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  std::ostringstream text;
  if (sigma(0) == 0 || sigma(sigma.size() - 1) <= kSingularRatio * sigma(0)) {
    diagnostics.m_plus_n_singular = true;
    diagnostics.kappa = kInf;
    diagnostics.verdict = BoundaryDiagnostics::Verdict::kNotApplicable;
    text << "M + N is singular (a periodic condition, for one): Lemma 9.1 and Theorems "
            "9.1-9.5 do not cover the problem; solved anyway (observed growth psi = "
         << Format(diagnostics.psi_observed) << ")";
    diagnostics.text = text.str();
    return diagnostics;
  }
  const Eigen::MatrixXd inverse_times_n = svd.solve(conditions.N);
  diagnostics.kappa = inverse_times_n.norm() == 0
                          ? 0.0
                          : Eigen::JacobiSVD<Eigen::MatrixXd>(inverse_times_n).singularValues()(0);
  if (diagnostics.kappa == 0) {
    diagnostics.psi_bound = kInf;
    diagnostics.verdict = BoundaryDiagnostics::Verdict::kHolds;
    text << "N = 0 (an initial-value problem): (9.5) holds for every T";
  } else {
    diagnostics.psi_bound = std::log1p(1 / diagnostics.kappa) / horizon;
    const bool fails = diagnostics.psi_observed >= diagnostics.psi_bound;
    diagnostics.verdict =
        fails ? BoundaryDiagnostics::Verdict::kFails : BoundaryDiagnostics::Verdict::kUndecided;
    text << "(9.5) needs psi < ln(1 + 1/kappa)/T = " << Format(diagnostics.psi_bound)
         << " with kappa = ||(M+N)^-1 N|| = " << Format(diagnostics.kappa) << "; the solution's "
         << "own growth is psi >= " << Format(diagnostics.psi_observed)
         << (fails ? ", so (9.5) fails: the existence theory of Sect. 9 does not cover the problem"
                   : ", which does not decide it");
  }
  diagnostics.text = text.str();
  return diagnostics;
}

std::string GridText(long steps, double h) {
  std::ostringstream text;
  text << steps << " steps (h = " << Format(h) << ")";
  return text.str();
}

}  // namespace

long ResolveSteps(const BoundaryValueOptions& options, double horizon) {
  if (options.steps > 0) return options.steps;
  const double steps = std::round(horizon / options.h);
  DVI_THROW_UNLESS(steps < 1e15, "h: " << options.h << " makes " << steps
                                       << " steps over the horizon " << horizon);
  return std::max(1L, static_cast<long>(steps));
}

BoundaryValueSolution SolveAggregate(const AggregateProblem& problem,
                                     const BoundaryValueOptions& options,
                                     const std::string& describe) {
  const Clock::time_point begin = Clock::now();
  options.Validate();
  DVI_THROW_UNLESS(std::isfinite(problem.horizon) && problem.horizon > 0,
                   "horizon: " << problem.horizon << " is not a positive final time");
  internal::CheckOutputTimesWithin(options.output_times, 0, problem.horizon);
  const long first_steps = ResolveSteps(options, problem.horizon);
  DVI_THROW_UNLESS(first_steps <= options.max_steps,
                   "steps: the first grid of " << first_steps << " steps exceeds max_steps = "
                                               << options.max_steps);

  if (options.backend == BoundaryValueBackend::kPetsc) {
    // Before any grid is solved, so that no rank starts what others refuse.
    PetscGridSolver();
    DVI_THROW_UNLESS(problem.set.r == 0,
                     "backend: \"petsc\" takes a box or polyhedral K (a box in its KKT "
                     "lifting), not one with a ball: use backend \"dvi\"");
  }
  BoundaryValueSolution solution;
  Trajectory& trajectory = solution.trajectory;
  GridSolver solver(problem, options);
  Grid grid = solver.Solve(first_steps, solver.WarmStart(first_steps), options.refine);
  const auto fail = [&](const Grid& failed) {
    std::ostringstream message;
    message << "the aggregate VI on " << GridText(failed.mcp.layout.steps, failed.mcp.h)
            << " was not solved: Newton " << ToString(failed.result.status) << ", "
            << failed.result.message;
    if (solver.failed_warm_start() > 0)
      message << " (from a cold start: its warm start, the grid of " << solver.failed_warm_start()
              << " steps, failed too)";
    trajectory.status = IntegrationStatus::kStepFailure;
    trajectory.message = message.str();
  };
  if (!grid.result.solved()) fail(grid);

  // Refinement: halve h until Richardson's estimate meets the tolerance.
  double previous_difference = 0;
  bool compared = false;  // the last grid has an error estimate
  while (options.refine && trajectory.succeeded()) {
    double scale = 0;
    for (long i = 0; i <= grid.mcp.layout.steps; ++i)
      scale = std::max(scale, grid.result.z.segment(grid.mcp.layout.State(i, 0), problem.n)
                                  .lpNorm<Eigen::Infinity>());
    const double tolerance = options.atol + options.rtol * scale;
    BoundaryValueGrid& record = solver.stats().grids.back();
    if (compared && record.error_estimate <= tolerance) break;
    const long next_steps = 2 * grid.mcp.layout.steps;
    if (next_steps > options.max_steps) {
      std::ostringstream message;
      message << "refinement stopped at " << GridText(grid.mcp.layout.steps, grid.mcp.h)
              << ": the next grid exceeds max_steps = " << options.max_steps;
      if (compared)
        message << ", and the estimated error " << Format(record.error_estimate)
                << " is above the tolerance " << Format(tolerance);
      trajectory.status = IntegrationStatus::kMaxSteps;
      trajectory.message = message.str();
      break;
    }
    const BoundaryValueLayout fine{grid.mcp.layout.n, grid.mcp.layout.m, grid.mcp.layout.block,
                                   next_steps};
    Grid next = solver.Solve(
        next_steps,
        Interpolate(grid, fine, problem.horizon / static_cast<double>(next_steps)), true);
    if (!next.result.solved()) {
      fail(next);
      break;
    }
    double difference = 0;
    for (long i = 0; i <= grid.mcp.layout.steps; ++i)
      difference = std::max(
          difference, (StateAt(next, static_cast<double>(i) * grid.mcp.h) -
                       grid.result.z.segment(grid.mcp.layout.State(i, 0), problem.n))
                          .lpNorm<Eigen::Infinity>());
    BoundaryValueGrid& next_record = solver.stats().grids.back();
    next_record.difference = difference;
    double order = 1;
    if (previous_difference > 0 && difference > 0) {
      next_record.observed_order = std::log2(previous_difference / difference);
      order = std::clamp(next_record.observed_order, kMinOrder, kMaxOrder);
    }
    next_record.error_estimate = difference / (std::exp2(order) - 1);
    previous_difference = difference;
    compared = true;
    grid = std::move(next);
  }

  BoundaryValueStats& stats = solver.stats();
  stats.unknowns = grid.mcp.layout.size();
  stats.nonzeros = grid.nonzeros;
  stats.iterations = grid.result.iterations;
  stats.residual = grid.result.residual;
  stats.message = grid.result.message;
  solution.newton = stats;
  IntegrationStats& counts = trajectory.stats;
  counts.steps = grid.mcp.layout.steps;
  counts.vi_solves = static_cast<long>(stats.grids.size());
  counts.solver_iterations = stats.total_iterations;
  counts.jacobian_evals = solver.jacobian_evals();
  counts.rhs_evals = solver.rhs_evals();
  counts.max_residual = grid.result.residual;
  if (trajectory.status != IntegrationStatus::kStepFailure) {
    trajectory.events = ModeChanges(grid, problem.set);
    Sample(grid, problem, options.output_times, trajectory);
    solution.diagnostics = Diagnose(problem.conditions, grid);
    std::ostringstream reason;
    reason << "boundary-value problem: aggregate VI (9.2)-(9.4) of " << describe << " on "
           << GridText(grid.mcp.layout.steps, grid.mcp.h) << ", " << stats.unknowns
           << " unknowns, semismooth Newton on "
           << (grid.by_backend ? "PETSc (SNES vinewtonrsls)"
                   : grid.mcp.matrix ? "KLU" : "a block LU of the step template")
           << ": "
           << stats.iterations << " iterations, residual "
           << Format(stats.residual);
    if (stats.grids.size() > 1)
      reason << " (" << stats.grids.size() << " grids, " << stats.total_iterations
             << " iterations in all)";
    if (options.refine && trajectory.succeeded())
      reason << "; refined to an estimated error of " << Format(stats.grids.back().error_estimate);
    trajectory.intervals.push_back({0, problem.horizon, IntegrationMethod::kBoundaryValue, reason.str()});
  }
  if (problem.certifier) {
    std::ostringstream basis;
    basis << "boundary-value: VI residual <= " << Certificate::kViSafety
          << "·(Newton's tolerance " << options.solver.tolerance
          << " + how far F moves between the row and its step's end) at every row";
    ConcludeCertificate(basis.str(), trajectory);
  }
  counts.wall_seconds = Seconds(begin);
  return solution;
}

}  // namespace dvi::internal
