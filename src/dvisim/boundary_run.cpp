// SPDX-License-Identifier: Apache-2.0
#include "boundary_run.hpp"

#include <type_traits>
#include <utility>
#include <variant>

#include "dvi/filippov.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {

Trajectory SolveBoundaryValueScene(const Scene& scene, BoundaryValueReport& report) {
  BoundaryValueOptions options = scene.bvp;
  options.output_times = OutputTimes(scene);
  const BoundaryConditions conditions =
      scene.boundary ? *scene.boundary : BoundaryConditions::Initial(scene.x0);
  BoundaryValueSolution solution = std::visit(
      [&](const auto& problem) -> BoundaryValueSolution {
        using Problem = std::decay_t<decltype(problem)>;
        if constexpr (std::is_same_v<Problem, LqNashGame>) {
          NashSolution game = SolveNashGame(problem, scene.horizon, options);
          report.hypotheses = std::move(game.hypotheses);
          report.adjoints = std::move(game.adjoints);
          return std::move(game.solution);
        } else if constexpr (std::is_same_v<Problem, FilippovSystem>) {
          return SolveBoundaryValue(problem.ToSeparable(), conditions, scene.horizon, options);
        } else if constexpr (std::is_same_v<Problem, ProjectedDynamics>) {
          throw InvalidInputError("bvp takes lcs, dvi, box-dvi, filippov and nash scenes, not pds");
        } else {
          return SolveBoundaryValue(problem, conditions, scene.horizon, options);
        }
      },
      scene.problem);
  report.newton = std::move(solution.newton);
  report.diagnostics = std::move(solution.diagnostics);
  return std::move(solution.trajectory);
}

void AddBoundaryValueSummary(const Scene& scene, const BoundaryValueReport& report,
                             nlohmann::ordered_json& summary) {
  const BoundaryValueStats& newton = report.newton;
  const bool nash = report.hypotheses.has_value();
  summary["steps"] = newton.grids.empty() ? 0 : newton.grids.back().steps;
  summary["h"] = newton.grids.empty() ? 0.0 : newton.grids.back().h;
  if (nash) {
    summary["scheme"] = "(a)-(e) of Sect. 10";
  } else {
    summary["theta"] = scene.bvp.theta;
    summary["scheme"] = std::string(ToString(scene.bvp.scheme));
  }
  nlohmann::ordered_json grids = nlohmann::ordered_json::array();
  for (const BoundaryValueGrid& grid : newton.grids) {
    nlohmann::ordered_json entry = {{"steps", grid.steps},
                                    {"h", grid.h},
                                    {"iterations", grid.iterations},
                                    {"residual", NumberToJson(grid.residual)},
                                    {"seconds", grid.seconds},
                                    {"refinement", grid.refinement}};
    if (grid.refinement && grid.difference > 0) {
      entry["difference"] = grid.difference;
      entry["observed_order"] = grid.observed_order;
      entry["error_estimate"] = grid.error_estimate;
    }
    grids.push_back(entry);
  }
  summary["newton"] = {{"iterations", newton.iterations},
                       {"total_iterations", newton.total_iterations},
                       {"residual", NumberToJson(newton.residual)},
                       {"unknowns", newton.unknowns},
                       {"nonzeros", newton.nonzeros},
                       {"message", newton.message},
                       {"grids", grids}};
  const BoundaryDiagnostics& d = report.diagnostics;
  summary["boundary"] = {{"m_plus_n_singular", d.m_plus_n_singular},
                         {"kappa", NumberToJson(d.kappa)},
                         {"psi_bound", NumberToJson(d.psi_bound)},
                         {"psi_observed", NumberToJson(d.psi_observed)},
                         {"condition_9_5", std::string(ToString(d.verdict))},
                         {"text", d.text}};
  if (!nash) return;
  const NashHypotheses& h = *report.hypotheses;
  nlohmann::ordered_json players = nlohmann::ordered_json::array();
  for (const NashHypotheses::Player& player : h.players)
    players.push_back({{"w_symmetric", player.w_symmetric},
                       {"w_min_eigenvalue", player.w_min_eigenvalue},
                       {"xi_symmetric", player.xi_symmetric},
                       {"xi_min_eigenvalue", player.xi_min_eigenvalue},
                       {"u_compact_polyhedron", player.u_compact_polyhedron}});
  summary["nash"] = {{"proposition_10_1", h.hold},
                     {"s_min_eigenvalue", h.s_min_eigenvalue},
                     {"players", players},
                     {"text", h.text}};
  summary["lambda_final"] = VectorToJson(
      report.adjoints.empty() ? Eigen::VectorXd() : Eigen::VectorXd(report.adjoints.back()));
}

}  // namespace dvi::dvisim
