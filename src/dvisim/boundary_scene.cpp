// SPDX-License-Identifier: Apache-2.0
#include "boundary_scene.hpp"

#include <string>
#include <utility>
#include <vector>

#include "problem_file.hpp"
#include "scene_fields.hpp"
#include "scene_file.hpp"

namespace dvi::dvisim {
namespace {

using nlohmann::json;

// A player's sizes, read before its blocks: a block's shape needs the
// rival's n and m.
struct PlayerSizes {
  int n = 0, m = 0;
};

Eigen::MatrixXd ReadDense(const json& value, const std::string& path, Eigen::Index rows,
                          Eigen::Index cols, const std::string& shape) {
  const MatrixField M = ReadMatrix(value, path);
  if (M.rows() != rows || M.cols() != cols)
    Fail(path, "is " + std::to_string(M.rows()) + "x" + std::to_string(M.cols()) + ", expected " +
                   std::to_string(rows) + "x" + std::to_string(cols) + " (" + shape + ")");
  return M.ToDense();
}

PlayerSizes ReadSizes(const json& player, const std::string& path, std::size_t index) {
  PlayerSizes sizes;
  const std::string v = std::to_string(index);
  const Eigen::VectorXd x0 = ReadVector(RequireField(player, "x0", path), Field(path, "x0"), false);
  if (x0.size() < 1) Fail(Field(path, "x0"), "is empty; each player needs a state");
  sizes.n = static_cast<int>(x0.size());
  const MatrixField H = ReadMatrix(RequireField(player, "H", path), Field(path, "H"));
  if (H.rows() != sizes.n || H.cols() < 1)
    Fail(Field(path, "H"), "is " + std::to_string(H.rows()) + "x" + std::to_string(H.cols()) +
                               ", expected " + std::to_string(sizes.n) +
                               " rows (n_" + v + ", the length of x0) and at least one column");
  sizes.m = static_cast<int>(H.cols());
  for (const auto& [key, size] : {std::pair{"n", sizes.n}, std::pair{"m", sizes.m}})
    if (const json* given = FindField(player, key)) {
      const long count = ReadCount(*given, Field(path, key));
      if (count != size)
        Fail(Field(path, key), "is " + std::to_string(count) + ", but " +
                                   (std::string(key) == "n" ? "x0 has " : "H has ") +
                                   std::to_string(size) + (std::string(key) == "n" ? " entries" : " columns"));
    }
  return sizes;
}

// One block per player, or all zero when the field is absent.
std::vector<Eigen::MatrixXd> ReadBlocks(const json& player, const std::string& path,
                                        const char* field, std::size_t index,
                                        const std::vector<PlayerSizes>& sizes, bool rows_are_states,
                                        bool cols_are_states) {
  std::vector<Eigen::MatrixXd> blocks;
  const json* value = FindField(player, field);
  if (!value) return blocks;
  const std::string list_path = Field(path, field);
  if (!value->is_array() || value->size() != sizes.size())
    Fail(list_path, "expected a list of " + std::to_string(sizes.size()) +
                        " matrices (one per player), got " + Describe(*value));
  const PlayerSizes& own = sizes[index];
  for (std::size_t w = 0; w < sizes.size(); ++w) {
    const std::string shape = std::string(rows_are_states ? "n_" : "m_") + std::to_string(index) +
                              " x " + (cols_are_states ? "n_" : "m_") + std::to_string(w);
    blocks.push_back(ReadDense((*value)[w], Indexed(list_path, w),
                               rows_are_states ? own.n : own.m,
                               cols_are_states ? sizes[w].n : sizes[w].m, shape));
  }
  return blocks;
}

Eigen::VectorXd ReadOptionalVector(const json& player, const std::string& path, const char* key,
                                   int size) {
  const json* value = FindField(player, key);
  return value ? ReadVector(*value, Field(path, key), false, size) : Eigen::VectorXd::Zero(size);
}

// Fields of the method object that concern another integrator.
bool BelongsToAnotherMethod(const std::string& key) {
  for (const char* other : {"gamma", "adaptive", "h_max", "solver", "ode", "linear_solver",
                            "max_events", "stepping_window", "max_handovers"})
    if (key == other) return true;
  return false;
}

}  // namespace

BoundaryConditions ReadBoundary(const json& value, int n) {
  const std::string path = "boundary";
  RequireObject(value, path);
  RejectUnknownFields(value, path, {"M", "N", "b"});
  BoundaryConditions conditions;
  const MatrixField M = ReadMatrix(RequireField(value, "M", path), Field(path, "M"));
  const MatrixField N = ReadMatrix(RequireField(value, "N", path), Field(path, "N"));
  CheckShape(M, Field(path, "M"), n, n);
  CheckShape(N, Field(path, "N"), n, n);
  conditions.M = M.ToDense();
  conditions.N = N.ToDense();
  conditions.b = ReadVector(RequireField(value, "b", path), Field(path, "b"), false, n);
  try {
    conditions.Validate(n);
  } catch (const InvalidInputError& error) {
    throw InputError(error.what());  // already names boundary.M, .N, .b or boundary
  }
  return conditions;
}

void ReadNash(const json& problem, const std::string& path, Scene& scene) {
  RejectUnknownFields(problem, path, {"type", "players"}, " for type nash");
  const std::string players_path = Field(path, "players");
  const json& players = RequireField(problem, "players", path);
  if (!players.is_array() || players.empty())
    Fail(players_path, "expected a non-empty list of players, got " + Describe(players));
  std::vector<PlayerSizes> sizes;
  for (std::size_t v = 0; v < players.size(); ++v) {
    const std::string player_path = Indexed(players_path, v);
    RequireObject(players[v], player_path);
    RejectUnknownFields(players[v], player_path,
                        {"n", "m", "x0", "G", "H", "r", "P", "Q", "R", "S", "p", "q", "c", "W", "U"});
    sizes.push_back(ReadSizes(players[v], player_path, v));
  }
  LqNashGame game;
  for (std::size_t v = 0; v < players.size(); ++v) {
    const json& data = players[v];
    const std::string player_path = Indexed(players_path, v);
    const int n = sizes[v].n, m = sizes[v].m;
    const std::string own = std::to_string(v);
    NashPlayer player;
    player.x0 = ReadVector(data["x0"], Field(player_path, "x0"), false);
    player.H = ReadMatrix(data["H"], Field(player_path, "H")).ToDense();
    player.G = ReadDense(RequireField(data, "G", player_path), Field(player_path, "G"), n, n,
                         "n_" + own + " x n_" + own);
    player.r = ReadOptionalVector(data, player_path, "r", n);
    player.p = ReadOptionalVector(data, player_path, "p", n);
    player.q = ReadOptionalVector(data, player_path, "q", m);
    player.c = ReadOptionalVector(data, player_path, "c", n);
    player.P = ReadBlocks(data, player_path, "P", v, sizes, true, true);
    player.Q = ReadBlocks(data, player_path, "Q", v, sizes, true, false);
    player.R = ReadBlocks(data, player_path, "R", v, sizes, false, true);
    player.S = ReadBlocks(data, player_path, "S", v, sizes, false, false);
    player.W = ReadBlocks(data, player_path, "W", v, sizes, true, true);
    const json* U = FindField(data, "U");
    player.U = U ? ReadSet(*U, Field(player_path, "U"), m) : ConvexSet::Whole(m);
    game.players.push_back(std::move(player));
  }
  WithPath(path, [&] { game.Validate(); });
  scene.n = game.n();
  scene.output_multipliers = game.m();
  scene.problem = std::move(game);
}

bool IsBoundaryValue(const Scene& scene) {
  return scene.boundary.has_value() || std::holds_alternative<LqNashGame>(scene.problem);
}

bool RunsBoundaryValue(const Scene& scene) {
  return scene.method == IntegrationMethod::kBoundaryValue ||
         (scene.method == IntegrationMethod::kAuto && IsBoundaryValue(scene));
}

std::string WhyNotMethod(const Scene& scene, IntegrationMethod method) {
  if (method == IntegrationMethod::kBoundaryValue) {
    if (std::holds_alternative<ProjectedDynamics>(scene.problem))
      return "\"bvp\" takes lcs, dvi, box-dvi, filippov and nash scenes, not pds";
    return "";
  }
  if ((method == IntegrationMethod::kTimeStepping || method == IntegrationMethod::kEventDriven) &&
      IsBoundaryValue(scene))
    return "\"" + std::string(ToString(method)) + "\" integrates from x0, but a " +
           (scene.boundary ? std::string("boundary") : std::string("nash")) +
           " scene fixes its states at both ends: use \"bvp\" (or \"auto\")";
  return "";
}

void ReadBoundaryValueMethod(const json& method, Scene& scene) {
  const std::string path = "method";
  BoundaryValueOptions& options = scene.bvp;
  const bool nash = std::holds_alternative<LqNashGame>(scene.problem);
  for (const auto& item : method.items())
    if (BelongsToAnotherMethod(item.key()))
      Fail(Field(path, item.key()), "is not used by \"bvp\" (it takes h or steps, theta, scheme, "
                                    "backend, tol, max_iterations, refine, rtol, atol, max_steps, max_wall)");
  RejectUnknownFields(method, path,
                      {"name", "h", "steps", "theta", "scheme", "backend", "tol", "max_iterations",
                       "refine", "rtol", "atol", "max_steps", "max_wall"},
                      " for bvp");
  const json* h = FindField(method, "h");
  const json* steps = FindField(method, "steps");
  if (h && steps) Fail(Field(path, "steps"), "give h or steps, not both");
  if (h) {
    options.h = ReadPositive(*h, Field(path, "h"));
    if (options.h > scene.horizon)
      Fail(Field(path, "h"), "is larger than the horizon " + Describe(scene.horizon));
  }
  if (steps) options.steps = ReadCount(*steps, Field(path, "steps"));
  for (const char* key : {"theta", "scheme"})
    if (nash && FindField(method, key))
      Fail(Field(path, key), "does not apply to a nash scene: its scheme (a)-(e) of Sect. 10 "
                             "fixes x implicit and lambda explicit");
  if (const json* theta = FindField(method, "theta"))
    options.theta = ReadUnitInterval(*theta, Field(path, "theta"));
  if (const json* scheme = FindField(method, "scheme")) {
    if (!scheme->is_string())
      Fail(Field(path, "scheme"), "expected \"9.3\" or \"9.11\", got " + Describe(*scheme));
    options.scheme = WithPath(Field(path, "scheme"),
                              [&] { return ParseBoundaryValueScheme(scheme->get<std::string>()); });
  }
  if (const json* backend = FindField(method, "backend")) {
    if (!backend->is_string())
      Fail(Field(path, "backend"), "expected \"dvi\" or \"petsc\", got " + Describe(*backend));
    options.backend = WithPath(Field(path, "backend"), [&] {
      return ParseBoundaryValueBackend(backend->get<std::string>());
    });
  }
  if (const json* tol = FindField(method, "tol"))
    options.solver.tolerance = ReadTolerance(*tol, Field(path, "tol"));
  if (const json* max_iterations = FindField(method, "max_iterations")) {
    const long count = ReadCount(*max_iterations, Field(path, "max_iterations"));
    if (count > 100000) Fail(Field(path, "max_iterations"), "expected at most 100000");
    options.solver.max_iterations = static_cast<int>(count);
  }
  if (const json* refine = FindField(method, "refine")) {
    if (!refine->is_boolean())
      Fail(Field(path, "refine"), "expected true or false, got " + Describe(*refine));
    options.refine = refine->get<bool>();
  }
  if (const json* rtol = FindField(method, "rtol"))
    options.rtol = ReadTolerance(*rtol, Field(path, "rtol"));
  if (const json* atol = FindField(method, "atol"))
    options.atol = ReadTolerance(*atol, Field(path, "atol"));
  if (const json* max_steps = FindField(method, "max_steps"))
    options.max_steps = ReadCount(*max_steps, Field(path, "max_steps"));
  // The first grid against max_steps: CheckSceneLimits, after the overrides.
  if (const json* max_wall = FindField(method, "max_wall"))
    scene.max_wall = ReadPositive(*max_wall, Field(path, "max_wall"));
}

}  // namespace dvi::dvisim
