// SPDX-License-Identifier: Apache-2.0
#include "scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "boundary_scene.hpp"
#include "dvi/error.hpp"
#include "expression.hpp"
#include "problem_file.hpp"
#include "scene_fields.hpp"
#include "scene_sources.hpp"

namespace dvi::dvisim {
namespace {

using nlohmann::json;

// Without method.h: a thousand steps over the horizon, fine enough to draw the
// trajectory and cheap enough to run at once; the user refines from there.
constexpr int kDefaultStepsPerHorizon = 1000;
// Shorter horizons are a matter of units: rescaled, they integrate as well.
constexpr double kMinHorizon = 1e-100;
// Without output.times and output.samples: this many rows, enough for a plot.
constexpr int kDefaultSamples = 501;

// An expression is a string, or a number standing for itself.
std::string ReadExpressionText(const json& value, const std::string& path) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number()) {
    std::ostringstream text;
    text.precision(17);
    text << value.get<double>();
    return text.str();
  }
  Fail(path, "expected an expression (a string or a number), got " + Describe(value));
}

std::vector<std::string> ReadExpressions(const json& value, const std::string& path,
                                         int expected_size = -1) {
  if (!value.is_array()) Fail(path, "expected an array of expressions, got " + Describe(value));
  if (expected_size >= 0 && value.size() != static_cast<std::size_t>(expected_size))
    Fail(path, "has " + std::to_string(value.size()) + " entries, expected " +
                   std::to_string(expected_size));
  std::vector<std::string> texts;
  for (std::size_t k = 0; k < value.size(); ++k)
    texts.push_back(ReadExpressionText(value[k], Indexed(path, k)));
  return texts;
}

SceneParams ReadParams(const json& problem, const std::string& path) {
  SceneParams params;
  const json* value = FindField(problem, "params");
  if (!value) return params;
  RequireObject(*value, path);
  for (const auto& item : value->items())
    params.emplace_back(item.key(), ReadNumber(item.value(), Field(path, item.key()), false));
  return params;
}

ConvexSet ReadOptionalSet(const json& problem, const std::string& path, int dim) {
  const json* set = FindField(problem, "set");
  return set ? ReadSet(*set, Field(path, "set"), dim) : ConvexSet::Orthant(dim);
}

void ReadLcs(const json& problem, const std::string& path, Scene& scene) {
  RejectUnknownFields(problem, path,
                      {"type", "A", "B", "C", "D", "p", "q", "set", "params", "breakpoints"},
                      " for type lcs");
  const MatrixField A = ReadMatrix(RequireField(problem, "A", path), Field(path, "A"));
  const MatrixField D = ReadMatrix(RequireField(problem, "D", path), Field(path, "D"));
  CheckShape(A, Field(path, "A"), A.rows(), A.rows());
  CheckShape(D, Field(path, "D"), D.rows(), D.rows());
  const Eigen::Index n = A.rows();
  const Eigen::Index m = D.rows();
  if (n < 1) Fail(Field(path, "A"), "is empty; an LCS needs at least one state");
  const MatrixField B = ReadMatrix(RequireField(problem, "B", path), Field(path, "B"));
  const MatrixField C = ReadMatrix(RequireField(problem, "C", path), Field(path, "C"));
  CheckShape(B, Field(path, "B"), n, m);
  CheckShape(C, Field(path, "C"), m, n);
  // p and q: numbers, or expressions in t (sources).
  const SceneParams params = ReadParams(problem, Field(path, "params"));
  Eigen::VectorXd p_value = Eigen::VectorXd::Zero(n), q_value = Eigen::VectorXd::Zero(m);
  TimeSource p_source, q_source, q_rate;
  if (const json* p = FindField(problem, "p"))
    ReadSourceVector(*p, Field(path, "p"), static_cast<int>(n), params, Field(path, "params"),
                     p_value, p_source, nullptr);
  if (const json* q = FindField(problem, "q"))
    ReadSourceVector(*q, Field(path, "q"), static_cast<int>(m), params, Field(path, "params"),
                     q_value, q_source, &q_rate);
  Lcs lcs = WithPath(path, [&] {
    return Lcs::Sparse(ToSparse(A), ToSparse(B), ToSparse(C), ToSparse(D), p_value, q_value);
  });
  lcs.K = ReadOptionalSet(problem, path, static_cast<int>(m));
  lcs.p_source = std::move(p_source);
  lcs.q_source = std::move(q_source);
  lcs.q_source_rate = std::move(q_rate);
  WithPath(path, [&] { lcs.Validate(); });
  scene.n = static_cast<int>(n);
  scene.output_multipliers = static_cast<int>(m);
  scene.problem = std::move(lcs);
}

void ReadDvi(const json& problem, const std::string& path, Scene& scene, bool box) {
  RejectUnknownFields(problem, path, {"type", "f", "F", "set", "params", "breakpoints"},
                      std::string(" for type ") + (box ? "box-dvi" : "dvi"));
  const json& f_json = RequireField(problem, "f", path);
  const json* F_json = FindField(problem, "F");
  if (!f_json.is_array() || f_json.empty())
    Fail(Field(path, "f"), "expected a non-empty array of expressions, got " + Describe(f_json));
  const int n = static_cast<int>(f_json.size());
  const std::vector<std::string> F_texts =
      F_json ? ReadExpressions(*F_json, Field(path, "F")) : std::vector<std::string>{};
  const int m = static_cast<int>(F_texts.size());
  const ExpressionVariables variables(n, m, ReadParams(problem, Field(path, "params")),
                                      Field(path, "params"));
  const ExpressionFunction f(ReadExpressions(f_json, Field(path, "f")), variables,
                             Field(path, "f"));
  const ExpressionFunction F(F_texts, variables, Field(path, "F"));
  Dvi dvi;
  dvi.n = n;
  dvi.m = m;
  dvi.f = f.Function();
  dvi.f_jacobian = f.Jacobian();
  dvi.F = F.Function();
  dvi.F_jacobian = F.Jacobian();
  dvi.F_time_derivative = F.TimeDerivative();
  dvi.F_affine_in_u = F.affine_in_u();
  dvi.K = ReadOptionalSet(problem, path, m);
  if (box && !dvi.K.IsBox())
    Fail(Field(path, "set"), "type box-dvi needs a box, got " + dvi.K.Describe());
  WithPath(path, [&] { dvi.Validate(); });
  scene.n = n;
  scene.output_multipliers = m;
  scene.problem = std::move(dvi);
}

void ReadPds(const json& problem, const std::string& path, Scene& scene) {
  RejectUnknownFields(problem, path, {"type", "F", "A", "c", "set", "params"}, " for type pds");
  const json* F_json = FindField(problem, "F");
  const json* A_json = FindField(problem, "A");
  if ((F_json != nullptr) == (A_json != nullptr))
    Fail(path, "give either \"F\" (expressions) or \"A\" and \"c\" (F(x) = A x - c)");
  ProjectedDynamics pds;
  int n = 0;
  if (A_json) {
    if (FindField(problem, "params"))
      Fail(Field(path, "params"), "only used with \"F\" expressions");
    const Eigen::MatrixXd A = ReadMatrix(*A_json, Field(path, "A")).ToDense();
    if (A.rows() < 1 || A.rows() != A.cols())
      Fail(Field(path, "A"), "is " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()) +
                                 ", expected a non-empty square matrix");
    n = static_cast<int>(A.rows());
    const json* c = FindField(problem, "c");
    const Eigen::VectorXd c_value =
        c ? ReadVector(*c, Field(path, "c"), false, n) : Eigen::VectorXd::Zero(n);
    const ConvexSet K = ReadOptionalSet(problem, path, n);
    pds = WithPath(path, [&] { return ProjectedDynamics::Affine(A, c_value, K); });
  } else {
    if (FindField(problem, "c")) Fail(Field(path, "c"), "only used with \"A\"");
    if (!F_json->is_array() || F_json->empty())
      Fail(Field(path, "F"), "expected a non-empty array of expressions, got " + Describe(*F_json));
    n = static_cast<int>(F_json->size());
    const ExpressionVariables variables(n, 0, ReadParams(problem, Field(path, "params")),
                                        Field(path, "params"));
    const ExpressionFunction F(ReadExpressions(*F_json, Field(path, "F")), variables,
                               Field(path, "F"));
    pds.K = ReadOptionalSet(problem, path, n);
    pds.F = F.StateFunction();
    pds.F_jacobian = F.StateJacobian();
  }
  WithPath(path, [&] { pds.Validate(); });
  scene.n = n;
  scene.output_multipliers = n;
  scene.problem = std::move(pds);
}

void ReadFilippov(const json& problem, const std::string& path, Scene& scene) {
  RejectUnknownFields(problem, path, {"type", "E", "p", "f0", "f1", "h", "params"},
                      " for type filippov");
  const json* E_json = FindField(problem, "E");
  const json* f0_json = FindField(problem, "f0");
  if ((E_json != nullptr) == (f0_json != nullptr))
    Fail(path, "give either \"E\" (and \"p\"), or \"f0\", \"f1\" and \"h\"");
  if (E_json) {
    for (const char* key : {"f1", "h", "params"})
      if (FindField(problem, key)) Fail(Field(path, key), "only used with \"f0\"");
    const Eigen::MatrixXd E = ReadMatrix(*E_json, Field(path, "E")).ToDense();
    if (E.rows() < 1 || E.rows() != E.cols())
      Fail(Field(path, "E"), "is " + std::to_string(E.rows()) + "x" + std::to_string(E.cols()) +
                                 ", expected a non-empty square matrix");
    const int n = static_cast<int>(E.rows());
    const json* p = FindField(problem, "p");
    const Eigen::VectorXd p_value =
        p ? ReadVector(*p, Field(path, "p"), false, n) : Eigen::VectorXd::Zero(n);
    scene.problem = WithPath(path, [&] { return FilippovSignLcs(E, p_value); });
    scene.filippov_sign_lcs = true;
    scene.n = n;
    scene.output_multipliers = n;
    return;
  }
  if (FindField(problem, "p")) Fail(Field(path, "p"), "only used with \"E\"");
  if (!f0_json->is_array() || f0_json->empty())
    Fail(Field(path, "f0"), "expected a non-empty array of expressions, got " + Describe(*f0_json));
  const int n = static_cast<int>(f0_json->size());
  const std::vector<std::string> h_texts =
      ReadExpressions(RequireField(problem, "h", path), Field(path, "h"));
  const int k = static_cast<int>(h_texts.size());
  if (k < 1) Fail(Field(path, "h"), "needs at least one switching function");
  const json& f1_json = RequireField(problem, "f1", path);
  const std::string f1_path = Field(path, "f1");
  if (!f1_json.is_array() || f1_json.size() != static_cast<std::size_t>(n))
    Fail(f1_path, "expected " + std::to_string(n) + " rows (one per state) of " +
                      std::to_string(k) + " expressions, got " + Describe(f1_json));
  std::vector<std::string> f1_texts;
  for (std::size_t r = 0; r < f1_json.size(); ++r) {
    const std::vector<std::string> row = ReadExpressions(f1_json[r], Indexed(f1_path, r), k);
    f1_texts.insert(f1_texts.end(), row.begin(), row.end());
  }
  const ExpressionVariables variables(n, 0, ReadParams(problem, Field(path, "params")),
                                      Field(path, "params"));
  const ExpressionFunction f0(ReadExpressions(*f0_json, Field(path, "f0")), variables,
                              Field(path, "f0"));
  // Parsed entry by entry first so that a message names f1[r][c], not the
  // flat row-major index the compiled function uses.
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < k; ++c)
      variables.Parse(
          f1_texts[static_cast<std::size_t>(r * k + c)],
          Indexed(Indexed(f1_path, static_cast<std::size_t>(r)), static_cast<std::size_t>(c)));
  const ExpressionFunction f1(f1_texts, variables, f1_path);
  const ExpressionFunction h(h_texts, variables, Field(path, "h"));
  FilippovSystem system;
  system.n = n;
  system.k = k;
  system.f0 = f0.StateFunction();
  system.f0_jacobian = f0.StateJacobian();
  system.f1 = f1.MatrixValue(n, k);
  system.h = h.StateFunction();
  system.h_jacobian = h.StateJacobian();
  WithPath(path, [&] { system.Validate(); });
  scene.n = n;
  scene.output_multipliers = k;
  scene.problem = std::move(system);
}

void ReadProblem(const json& problem, Scene& scene) {
  const std::string path = "problem";
  RequireObject(problem, path);
  const json& type = RequireField(problem, "type", path);
  if (!type.is_string()) Fail(Field(path, "type"), "expected a string, got " + Describe(type));
  scene.type = type.get<std::string>();
  if (scene.type == "lcs") {
    ReadLcs(problem, path, scene);
  } else if (scene.type == "dvi" || scene.type == "box-dvi") {
    ReadDvi(problem, path, scene, scene.type == "box-dvi");
  } else if (scene.type == "pds") {
    ReadPds(problem, path, scene);
  } else if (scene.type == "filippov") {
    ReadFilippov(problem, path, scene);
  } else if (scene.type == "nash") {
    ReadNash(problem, path, scene);
  } else {
    Fail(Field(path, "type"), "unknown type " + Describe(type) +
                                  " (expected lcs, dvi, box-dvi, pds, filippov or nash)");
  }
}

}  // namespace

TimeSteppingOptions SceneSteppingDefaults() {
  TimeSteppingOptions stepping;
  stepping.rtol = 1e-6;
  stepping.atol = 1e-9;
  stepping.max_steps = 100'000'000;
  return stepping;
}

EventDrivenOptions SceneEventDefaults() {
  EventDrivenOptions event;
  event.max_steps = 1'000'000;
  return event;
}

namespace {

// problem.breakpoints of an lcs, dvi or box-dvi scene (the other types
// refuse the field), read once the horizon is known.
void ReadProblemBreakpoints(const json& problem, Scene& scene) {
  const json* value = FindField(problem, "breakpoints");
  if (!value) return;
  std::vector<double> times =
      ReadBreakpoints(*value, "problem.breakpoints", ReadParams(problem, "problem.params"),
                      "problem.params", scene.horizon);
  if (Lcs* lcs = std::get_if<Lcs>(&scene.problem)) lcs->breakpoints = std::move(times);
  if (Dvi* dvi = std::get_if<Dvi>(&scene.problem)) dvi->breakpoints = std::move(times);
}

OdeMethod ReadOdeMethod(const json& value, const std::string& path) {
  for (const OdeMethod method : {OdeMethod::kBdf, OdeMethod::kAdams, OdeMethod::kAuto})
    if (value.is_string() && value.get<std::string>() == ToString(method)) return method;
  Fail(path, "expected \"bdf\", \"adams\" or \"auto\", got " + Describe(value));
}

LinearSolver ReadLinearSolver(const json& value, const std::string& path) {
  for (const LinearSolver solver : {LinearSolver::kAuto, LinearSolver::kDense, LinearSolver::kKlu})
    if (value.is_string() && value.get<std::string>() == ToString(solver)) return solver;
  Fail(path, "expected \"auto\", \"dense\" or \"klu\", got " + Describe(value));
}

// The fields shared by both integrators set both option sets, so that auto
// honours them whichever it picks.
void ReadMethodFields(const json& method, Scene& scene) {
  const std::string path = "method";
  TimeSteppingOptions& stepping = scene.stepping;
  EventDrivenOptions& event = scene.event;
  if (const json* h = FindField(method, "h")) stepping.h = ReadPositive(*h, Field(path, "h"));
  if (stepping.h > scene.horizon)
    Fail(Field(path, "h"), "is larger than the horizon " + Describe(scene.horizon));
  if (const json* theta = FindField(method, "theta"))
    stepping.theta = ReadUnitInterval(*theta, Field(path, "theta"));
  if (const json* gamma = FindField(method, "gamma"))
    stepping.gamma = ReadUnitInterval(*gamma, Field(path, "gamma"));
  const json* rtol = FindField(method, "rtol");
  if (rtol) stepping.rtol = event.rtol = ReadTolerance(*rtol, Field(path, "rtol"));
  if (const json* atol = FindField(method, "atol"); atol && atol->is_array()) {
    // One per state (CVodeSVtolerances); the scalar atol, for what takes one
    // number (bvp, messages), is their largest.
    if (atol->size() != static_cast<std::size_t>(scene.x0.size()))
      Fail(Field(path, "atol"), "expected a number or an array of " +
                                    std::to_string(scene.x0.size()) + " tolerances (one per state), got " +
                                    std::to_string(atol->size()) + " entries");
    Eigen::VectorXd per_state(scene.x0.size());
    for (std::size_t i = 0; i < atol->size(); ++i)
      per_state(static_cast<Eigen::Index>(i)) =
          ReadTolerance((*atol)[i], Field(path, "atol") + "[" + std::to_string(i) + "]");
    stepping.atol_per_state = event.atol_per_state = per_state;
    stepping.atol = event.atol = per_state.maxCoeff();
  } else if (atol) {
    stepping.atol = event.atol = ReadTolerance(*atol, Field(path, "atol"));
  } else if (rtol)  // rtol alone: atol follows it (docs/scenes.md)
    stepping.atol = event.atol = AtolFollowingRtol(event.rtol);
  if (const json* scheme = FindField(method, "scheme")) {
    if (!scheme->is_string())
      Fail(Field(path, "scheme"), "expected a string, got " + Describe(*scheme));
    stepping.scheme = WithPath(Field(path, "scheme"),
                               [&] { return ParseSteppingScheme(scheme->get<std::string>()); });
  }
  if (const json* adaptive = FindField(method, "adaptive")) {
    if (!adaptive->is_boolean())
      Fail(Field(path, "adaptive"), "expected true or false, got " + Describe(*adaptive));
    stepping.adaptive = adaptive->get<bool>();
  }
  if (const json* h_max = FindField(method, "h_max"))
    stepping.h_max = event.h_max = ReadPositive(*h_max, Field(path, "h_max"));
  if (const json* max_steps = FindField(method, "max_steps"))
    stepping.max_steps = event.max_steps = ReadCount(*max_steps, Field(path, "max_steps"));
  if (const json* solver = FindField(method, "solver"))
    stepping.solver.method = event.solver.method = ReadSolver(*solver, Field(path, "solver"));
  if (const json* tol = FindField(method, "tol"))
    stepping.solver.tolerance = event.solver.tolerance = ReadTolerance(*tol, Field(path, "tol"));
  if (const json* ode = FindField(method, "ode"))
    event.method = ReadOdeMethod(*ode, Field(path, "ode"));
  if (const json* max_events = FindField(method, "max_events"))
    event.max_events = ReadCount(*max_events, Field(path, "max_events"));
  if (const json* linear_solver = FindField(method, "linear_solver")) {
    event.linear_solver = ReadLinearSolver(*linear_solver, Field(path, "linear_solver"));
    const Lcs* lcs = std::get_if<Lcs>(&scene.problem);
    if (event.linear_solver == LinearSolver::kKlu && !(lcs && lcs->K.IsBox()))
      Fail(Field(path, "linear_solver"),
           "\"klu\" needs an lcs scene on a box set (the mode Jacobian comes from its sparse "
           "matrices); this is a " + scene.type + " scene");
  }
  if (const json* window = FindField(method, "stepping_window")) {
    scene.stepping_window = ReadPositive(*window, Field(path, "stepping_window"));
    if (scene.stepping_window > 1)
      Fail(Field(path, "stepping_window"), "expected a number in (0, 1], got " + Describe(*window));
  }
  if (const json* window_rtol = FindField(method, "window_rtol"))
    scene.window_rtol = ReadTolerance(*window_rtol, Field(path, "window_rtol"));
  if (const json* window_atol = FindField(method, "window_atol"))
    scene.window_atol = ReadTolerance(*window_atol, Field(path, "window_atol"));
  if (const json* zeno = FindField(method, "extrapolate_zeno")) {
    if (!zeno->is_boolean())
      Fail(Field(path, "extrapolate_zeno"), "expected true or false, got " + Describe(*zeno));
    scene.extrapolate_zeno = zeno->get<bool>();
  }
  if (const json* max_wall = FindField(method, "max_wall"))
    scene.max_wall = ReadPositive(*max_wall, Field(path, "max_wall"));
  if (const json* max_handovers = FindField(method, "max_handovers")) {
    const long count = ReadCount(*max_handovers, Field(path, "max_handovers"));
    if (count > std::numeric_limits<int>::max())
      Fail(Field(path, "max_handovers"), "expected at most " +
                                             std::to_string(std::numeric_limits<int>::max()) +
                                             ", got " + Describe(*max_handovers));
    scene.max_handovers = static_cast<int>(count);
  }
}

void ReadMethod(const json* method, Scene& scene) {
  const std::string path = "method";
  scene.stepping.h = scene.horizon / kDefaultStepsPerHorizon;
  scene.bvp.h = scene.stepping.h;
  if (!method) return;
  if (method->is_string()) {
    scene.method = ReadSceneMethod(method->get<std::string>(), path);
  } else {
    RequireObject(*method, path);
    if (const json* name = FindField(*method, "name")) {
      if (!name->is_string())
        Fail(Field(path, "name"), "expected a string, got " + Describe(*name));
      scene.method = ReadSceneMethod(name->get<std::string>(), Field(path, "name"));
    }
    if (!RunsBoundaryValue(scene))
      RejectUnknownFields(*method, path,
                          {"name", "h", "theta", "gamma", "rtol", "atol", "scheme", "adaptive",
                           "h_max", "max_steps", "solver", "tol", "ode", "linear_solver",
                           "max_events", "stepping_window", "max_handovers", "max_wall",
                           "window_rtol", "window_atol", "extrapolate_zeno"});
  }
  const std::string name_path = method->is_string() ? path : Field(path, "name");
  if (const std::string why = WhyNotMethod(scene, scene.method); !why.empty()) Fail(name_path, why);
  if (scene.method == IntegrationMethod::kEventDriven) {
    const std::string why = WhyNotEventDriven(scene);
    if (!why.empty()) Fail(name_path, EventDrivenMismatch(why));
  }
  if (method->is_string()) return;
  if (RunsBoundaryValue(scene))
    ReadBoundaryValueMethod(*method, scene);
  else
    ReadMethodFields(*method, scene);
}

void ReadOutput(const json* output, Scene& scene) {
  const std::string path = "output";
  SceneOutput& out = scene.output;
  out.dir = "out/" + (scene.name.empty() ? std::string("scene") : scene.name);
  if (output) {
    RequireObject(*output, path);
    RejectUnknownFields(*output, path, {"dir", "times", "samples", "plot"});
    if (const json* dir = FindField(*output, "dir")) {
      out.dir_source = "output.dir";
      if (!dir->is_string() || dir->get<std::string>().empty())
        Fail(Field(path, "dir"), "expected a non-empty string, got " + Describe(*dir));
      out.dir = dir->get<std::string>();
    }
    if (const json* times = FindField(*output, "times")) {
      const Eigen::VectorXd values = ReadVector(*times, Field(path, "times"), false);
      for (Eigen::Index k = 0; k < values.size(); ++k) {
        if (values(k) < 0 || values(k) > scene.horizon)
          Fail(Indexed(Field(path, "times"), static_cast<std::size_t>(k)),
               Describe(values(k)) + " is outside [0, horizon] = [0, " + Describe(scene.horizon) +
                   "]");
        out.times.push_back(values(k));
      }
    }
    if (const json* samples = FindField(*output, "samples")) {
      if (!samples->is_number_integer() || samples->get<long>() < 2 ||
          samples->get<long>() > 10'000'000)
        Fail(Field(path, "samples"),
             "expected an integer in [2, 10000000], got " + Describe(*samples));
      out.samples = samples->get<int>();
    }
    if (const json* plot = FindField(*output, "plot")) {
      if (!plot->is_boolean())
        Fail(Field(path, "plot"), "expected true or false, got " + Describe(*plot));
      out.plot = plot->get<bool>();
    }
  }
  if (out.times.empty() && out.samples == 0) out.samples = kDefaultSamples;
}

}  // namespace

std::string EventDrivenMismatch(const std::string& why) {
  return "\"event\" needs a DVI with a multiplier u (Sect. 5), or a pds scene in the form "
         "(2.10); " +
         why + " (use \"auto\" or \"stepping\")";
}

std::string WhyNotEventDriven(const Scene& scene) {
  // Any K of an lcs or dvi: a box directly, other sets through their KKT
  // system (event_driven.hpp). A pds scene through (2.10), one multiplier
  // per constraint g_i(x) ≤ 0 of K.
  if (const auto* pds = std::get_if<ProjectedDynamics>(&scene.problem);
      pds && !pds->K.IsPolyhedral() && pds->K.kind() != ConvexSet::Kind::kBall)
    return "the pds scene's K = " + pds->K.Describe() +
           " has no form (2.10): it needs K polyhedral or a ball";
  return "";
}

std::vector<double> OutputTimes(const Scene& scene) {
  std::vector<double> times = scene.output.times;
  const int samples = scene.output.samples;
  for (int k = 0; k < samples; ++k) {
    double t = scene.horizon * k / (samples - 1);
    // T·k overflows for T near the largest double; T·(k/(samples − 1)) does not.
    if (!std::isfinite(t)) t = scene.horizon * (static_cast<double>(k) / (samples - 1));
    times.push_back(k + 1 == samples ? scene.horizon : t);
  }
  std::sort(times.begin(), times.end());
  std::vector<double> merged;
  for (const double t : times)
    if (merged.empty() || t - merged.back() > kSameRowFraction * scene.horizon) merged.push_back(t);
  return merged;
}

Scene ParseScene(const std::string& text) {
  const json root = ParseJson(text);
  if (!root.is_object()) Fail("(file)", "expected a JSON object, got " + Describe(root));
  RejectUnknownFields(root, "",
                      {"name", "description", "problem", "x0", "boundary", "horizon", "method",
                       "output", "exact", "study"});
  Scene scene;
  if (const json* name = FindField(root, "name")) {
    if (!name->is_string()) Fail("name", "expected a string, got " + Describe(*name));
    scene.name = name->get<std::string>();
    // One line of text: it titles the plot (gnuplot failed on a line break
    // after the run) and names the default output directory.
    if (std::any_of(scene.name.begin(), scene.name.end(),
                    [](unsigned char c) { return c < 0x20 || c == 0x7f; }))
      Fail("name", "contains a control character (a line break?); it must be one line of text");
  }
  if (const json* description = FindField(root, "description");
      description && !description->is_string())
    Fail("description", "expected a string, got " + Describe(*description));
  ReadProblem(RequireField(root, "problem", "(file)"), scene);
  // x(0) = x0, or the two-point conditions of a boundary scene; a nash
  // scene's players carry their own x0.
  const json* x0 = FindField(root, "x0");
  const json* boundary = FindField(root, "boundary");
  if (std::holds_alternative<LqNashGame>(scene.problem)) {
    for (const auto& [field, value] : {std::pair{"x0", x0}, std::pair{"boundary", boundary}})
      if (value)
        Fail(field, "a nash scene gives each player's x0 in problem.players (the game's own "
                    "boundary conditions are x(0) = x0 and lambda(T) = c + W x(T))");
  } else if (boundary) {
    if (x0) Fail("x0", "a boundary scene gives \"boundary\" in place of \"x0\"; remove one");
    scene.boundary = ReadBoundary(*boundary, scene.n);
  } else {
    scene.x0 = ReadVector(RequireField(root, "x0", "(file)"), "x0", false, scene.n);
  }
  scene.horizon = ReadPositive(RequireField(root, "horizon", "(file)"), "horizon");
  if (scene.horizon < kMinHorizon)
    Fail("horizon", "is " + Describe(root["horizon"]) +
                        ", below 1e-100: CVODE's first-step estimate underflows near 1e-160, "
                        "so rescale time");
  ReadProblemBreakpoints(root["problem"], scene);
  ReadMethod(FindField(root, "method"), scene);
  ReadOutput(FindField(root, "output"), scene);
  if (const json* exact = FindField(root, "exact"))
    scene.exact.emplace(*exact, "exact", scene.n, scene.horizon, scene.x0);
  if (const json* study = FindField(root, "study"))
    scene.study = ReadStudySettings(*study, "study", scene.horizon, scene.stepping.max_steps);
  return scene;
}

Scene ReadScene(const std::string& path) {
  return ParseFile(path, ParseScene);
}

}  // namespace dvi::dvisim
