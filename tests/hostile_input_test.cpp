// SPDX-License-Identifier: Apache-2.0
// Hostile input: every scene, problem file and command line a user's typo,
// script or generator can produce is answered by the built dvisim with a
// result or a clear error, never a crash, a hang or an answer of inf
// (issue 28). One table row per input: the exit code, the words the message
// must contain, and, for any exit but 0, no file left behind; exit 0 must
// leave complete, finite output. Each row runs dvisim in a directory of its
// own under a time limit, so a hang fails its row instead of the suite.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// Every row ends in well under a second; a row still running after this
// long hangs (the defects this suite pins took from 8 s to forever).
constexpr int kHangSeconds = 60;

struct HostileCase {
  const char* name;
  std::string input;  ///< Written to input.json (a scene or a problem file); may be empty.
  std::string args;   ///< dvisim's arguments; the input file is input.json.
  int exit_code;
  std::vector<std::string> words;  ///< The message on stderr must contain each.
};

std::ostream& operator<<(std::ostream& out, const HostileCase& c) { return out << c.name; }

// A scene of one state, stepped (fast) unless the rest says otherwise.
std::string Dvi(const std::string& f, const std::string& more = "",
                const std::string& rest = R"("method": "stepping")") {
  return R"({"problem": {"type": "dvi", "f": [")" + f + "\"]" + more +
         R"(}, "x0": [1], "horizon": 1, "output": {"samples": 11}, )" + rest + "}";
}
// A box-dvi with one u: f and F given.
std::string BoxDvi(const std::string& f, const std::string& F) {
  return R"({"problem": {"type": "box-dvi", "f": [")" + f + R"("], "F": [")" + F +
         R"("]}, "x0": [1], "horizon": 1, "method": "stepping", "output": {"samples": 11}})";
}
// A filippov scene in f0/f1/h form with switching function h.
std::string Filippov(const std::string& h) {
  return R"({"problem": {"type": "filippov", "f0": ["0.5"], "f1": [["-1"]], "h": [")" + h +
         R"("]}, "x0": [1], "horizon": 1, "method": "stepping", "output": {"samples": 11}})";
}
// A scene around a problem object, stepped.
std::string Problem(const std::string& problem, const std::string& x0 = "[1]",
                    const std::string& rest = R"("method": "stepping")") {
  return R"({"problem": )" + problem + R"(, "x0": )" + x0 +
         R"(, "horizon": 1, "output": {"samples": 11}, )" + rest + "}";
}
// The well-formed scene the top-level rows break one field of.
std::string Valid(const std::string& rest) {
  return R"({"problem": {"type": "dvi", "f": ["-x1"]}, )" + rest + "}";
}
const std::string kLcs1 = R"({"type": "lcs", "A": [[0]], "B": [[1]], "C": [[1]], "D": [[1]])";
// The set of a dvi with one u: f = -x1 + u1, F = u1 - x1 on `set`.
std::string OnSet(const std::string& set) {
  return Problem(R"({"type": "dvi", "f": ["-x1 + u1"], "F": ["u1 - x1"], "set": )" + set + "}");
}

// A boundary scene x' = -x, M x(0) + N x(T) = b, solved by bvp (auto),
// with `method` fields added.
std::string Boundary(const std::string& M, const std::string& N, const std::string& b,
                     const std::string& method = "") {
  return R"({"problem": {"type": "dvi", "f": ["-x1"]}, "boundary": {"M": )" + M + R"(, "N": )" +
         N + R"(, "b": )" + b +
         R"(}, "horizon": 1, "output": {"samples": 11}, "method": {"name": "bvp", "steps": 100)" +
         method + "}}";
}
// A nash scene of one scalar player (x' = -x + u) with the fields `player`
// added (none of x0, G, H) and `rest` added to the scene.
std::string Nash(const std::string& player, const std::string& rest = "") {
  return R"({"problem": {"type": "nash", "players": [{"x0": [1], "G": [[-1]], "H": [[1]], )" +
         player + R"(}]}, "horizon": 1, "output": {"samples": 11})" + rest + "}";
}

const std::vector<HostileCase>& Cases() {
  static const std::vector<HostileCase> cases{
      // --- malformed JSON -------------------------------------------------
      {"EmptyFile", "", "run input.json", 2, {"malformed JSON"}},
      {"Truncated", R"({"problem": )", "run input.json", 2, {"malformed JSON at line 1"}},
      {"TrailingComma", R"({"x0": [1,], "horizon": 1})", "run input.json", 2, {"malformed JSON"}},
      {"NotAnObject", "[1, 2]", "run input.json", 2, {"expected a JSON object"}},
      {"DuplicateKey", Valid(R"("x0": [1], "horizon": 1, "horizon": 2)"), "run input.json", 2,
       {"duplicate key \"horizon\""}},
      {"DeepNesting", std::string(300, '[') + std::string(300, ']'), "run input.json", 2,
       {"nested deeper than 256"}},
      {"NumberBeyondDouble", Valid(R"("x0": [1], "horizon": 1e400)"), "run input.json", 2,
       {"beyond double precision"}},
      {"BinaryGarbage", std::string("\x01\x02\xff\xfe", 4), "run input.json", 2,
       {"malformed JSON"}},
      {"NaNLiteral", Valid(R"("x0": [NaN], "horizon": 1)"), "run input.json", 2,
       {"malformed JSON"}},
      {"Comment", "// scene\n" + Valid(R"("x0": [1], "horizon": 1)"), "run input.json", 2,
       {"malformed JSON"}},
      // --- fields and types ------------------------------------------------
      {"UnknownTopField", Valid(R"("x0": [1], "horizon": 1, "horizn": 2)"), "run input.json", 2,
       {"unknown field \"horizn\""}},
      {"MissingProblem", R"({"x0": [1], "horizon": 1})", "run input.json", 2,
       {"missing field \"problem\""}},
      {"MissingX0", Valid(R"("horizon": 1)"), "run input.json", 2, {"missing field \"x0\""}},
      {"MissingHorizon", Valid(R"("x0": [1])"), "run input.json", 2,
       {"missing field \"horizon\""}},
      {"ProblemNotObject", R"({"problem": 3, "x0": [1], "horizon": 1})", "run input.json", 2,
       {"problem", "expected an object"}},
      {"TypeNotString", R"({"problem": {"type": 1}, "x0": [1], "horizon": 1})", "run input.json",
       2, {"problem.type: expected a string"}},
      {"TypeUnknown", R"({"problem": {"type": "ode"}, "x0": [1], "horizon": 1})",
       "run input.json", 2, {"problem.type: unknown type \"ode\""}},
      {"TypeNashWithoutPlayers", R"({"problem": {"type": "nash"}, "x0": [1], "horizon": 1})",
       "run input.json", 2, {"problem", "missing field \"players\""}},
      {"BoundaryBlockWithX0", Valid(R"("x0": [1], "horizon": 1, "boundary": {})"),
       "run input.json", 2, {"x0", "in place of \"x0\""}},
      {"NameWithLineBreak", Valid(R"("name": "a\nb", "x0": [1], "horizon": 1)"),
       "run input.json", 2, {"name", "control character"}},
      {"NameDotDot", Valid(R"("name": "..", "x0": [1], "horizon": 1)"), "run input.json", 2,
       {"name", "outside out/"}},
      {"NameWithSlash", Valid(R"("name": "../escape", "x0": [1], "horizon": 1)"),
       "run input.json", 2, {"name", "outside out/"}},
      {"DescriptionNotString", Valid(R"("description": 1, "x0": [1], "horizon": 1)"),
       "run input.json", 2, {"description: expected a string"}},
      {"X0NotArray", Valid(R"("x0": "1", "horizon": 1)"), "run input.json", 2,
       {"x0: expected an array"}},
      {"X0WrongLength", Valid(R"("x0": [1, 2], "horizon": 1)"), "run input.json", 2,
       {"x0: has 2 entries, expected 1"}},
      {"X0Infinite", Valid(R"("x0": ["inf"], "horizon": 1)"), "run input.json", 2,
       {"x0[0]: expected a finite number"}},
      {"X0Null", Valid(R"("x0": [null], "horizon": 1)"), "run input.json", 2,
       {"x0[0]: expected a number"}},
      {"HorizonZero", Valid(R"("x0": [1], "horizon": 0)"), "run input.json", 2,
       {"horizon: expected a number > 0"}},
      {"HorizonNegative", Valid(R"("x0": [1], "horizon": -1)"), "run input.json", 2,
       {"horizon: expected a number > 0"}},
      {"HorizonTiny", Valid(R"("x0": [1], "horizon": 1e-200)"), "run input.json", 2,
       {"horizon", "below 1e-100"}},
      {"HorizonString", Valid(R"("x0": [1], "horizon": "1")"), "run input.json", 2,
       {"horizon: expected a number"}},
      // --- method --------------------------------------------------------------
      {"MethodUnknown", Dvi("-x1", "", R"("method": "rk4")"), "run input.json", 2,
       {"method: unknown method \"rk4\" (expected auto, stepping, event or bvp)"}},
      // event-ida names an interval's method (IntegrationMethod::kModeDae), not a scene's.
      {"MethodNameModeDae", Dvi("-x1", "", R"("method": {"name": "event-ida"})"), "run input.json",
       2, {"method.name: unknown method \"event-ida\" (expected auto, stepping, event or bvp)"}},
      {"MethodBvp", Dvi("-x1", "", R"("method": "bvp")"), "run input.json", 0, {}},
      {"StepNegative", Dvi("-x1", "", R"("method": {"name": "stepping", "h": -1})"),
       "run input.json", 2, {"method.h: expected a number > 0"}},
      {"StepBeyondHorizon", Dvi("-x1", "", R"("method": {"name": "stepping", "h": 2})"),
       "run input.json", 2, {"method.h", "larger than the horizon"}},
      {"AtolArrayWrongLength", Dvi("-x1", "", R"("method": {"name": "event", "atol": [1e-6, 1e-6]})"),
       "run input.json", 2, {"method.atol", "an array of 1 tolerances (one per state), got 2"}},
      {"AtolArrayNegativeEntry", Dvi("-x1", "", R"("method": {"name": "event", "atol": [-1]})"),
       "run input.json", 2, {"method.atol[0]", "expected a tolerance in (0, 1)"}},
      {"ThetaTwo", Dvi("-x1", "", R"("method": {"theta": 2})"), "run input.json", 2,
       {"method.theta", "[0, 1]"}},
      {"GammaNegative", Dvi("-x1", "", R"("method": {"gamma": -1})"), "run input.json", 2,
       {"method.gamma", "[0, 1]"}},
      {"RtolZero", Dvi("-x1", "", R"("method": {"rtol": 0})"), "run input.json", 2,
       {"method.rtol", "(0, 1)"}},
      {"AtolTwo", Dvi("-x1", "", R"("method": {"atol": 2})"), "run input.json", 2,
       {"method.atol", "(0, 1)"}},
      {"SchemeUnknown", Dvi("-x1", "", R"("method": {"scheme": "9.9"})"), "run input.json", 2,
       {"method.scheme", "unknown stepping scheme \"9.9\""}},
      {"AdaptiveNotBool", Dvi("-x1", "", R"("method": {"adaptive": "yes"})"), "run input.json", 2,
       {"method.adaptive: expected true or false"}},
      {"MaxStepsZero", Dvi("-x1", "", R"("method": {"max_steps": 0})"), "run input.json", 2,
       {"method.max_steps: expected an integer ≥ 1"}},
      {"MaxStepsFraction", Dvi("-x1", "", R"("method": {"max_steps": 1.5})"), "run input.json", 2,
       {"method.max_steps: expected an integer ≥ 1"}},
      {"SolverUnknown", Dvi("-x1", "", R"("method": {"solver": "magic"})"), "run input.json", 2,
       {"method.solver", "unknown solver method \"magic\""}},
      {"OdeUnknown", Dvi("-x1", "", R"("method": {"ode": "rk4"})"), "run input.json", 2,
       {"method.ode", "\"bdf\", \"adams\" or \"auto\""}},
      {"KluOnDvi", Dvi("-x1", "", R"("method": {"linear_solver": "klu"})"), "run input.json", 2,
       {"method.linear_solver", "needs an lcs scene"}},
      {"SteppingWindowTwo", Dvi("-x1", "", R"("method": {"stepping_window": 2})"),
       "run input.json", 2, {"method.stepping_window", "(0, 1]"}},
      {"ExtrapolateZenoNotABoolean", Dvi("-x1", "", R"("method": {"extrapolate_zeno": "yes"})"),
       "run input.json", 2, {"method.extrapolate_zeno", "expected true or false"}},
      {"MaxHandoversHuge", Dvi("-x1", "", R"("method": {"max_handovers": 1000000000000})"),
       "run input.json", 2, {"method.max_handovers", "expected at most"}},
      {"MaxWallZero", Dvi("-x1", "", R"("method": {"max_wall": 0})"), "run input.json", 2,
       {"method.max_wall: expected a number > 0"}},
      {"MethodUnknownField", Dvi("-x1", "", R"("method": {"step": 0.1})"), "run input.json", 2,
       {"method: unknown field \"step\""}},
      {"EventOnPdsWithoutKkt",
       Problem(R"({"type": "pds", "A": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "set": {"product":
         [{"ball": {"center": [0, 0], "radius": 1}}, {"box": {"lower": [0], "upper": [1]}}]}})",
               "[0, 0, 0.5]", R"("method": "event")"),
       "run input.json", 2, {"method", "\"event\" needs a DVI"}},
      // --- output ----------------------------------------------------------
      {"SamplesOne", Valid(R"("x0": [1], "horizon": 1, "output": {"samples": 1})"),
       "run input.json", 2, {"output.samples", "expected an integer in [2, 10000000]"}},
      {"SamplesTooMany",
       Valid(R"("x0": [1], "horizon": 1, "output": {"samples": 100000000})"), "run input.json",
       2, {"output.samples", "expected an integer in [2, 10000000]"}},
      {"TimesOutsideHorizon",
       Valid(R"("x0": [1], "horizon": 1, "output": {"times": [0.5, 2]})"), "run input.json", 2,
       {"output.times[1]", "outside [0, horizon]"}},
      {"PlotNotBool", Valid(R"("x0": [1], "horizon": 1, "output": {"plot": 1})"),
       "run input.json", 2, {"output.plot: expected true or false"}},
      {"DirEmpty", Valid(R"("x0": [1], "horizon": 1, "output": {"dir": ""})"), "run input.json",
       2, {"output.dir: expected a non-empty string"}},
      {"OutputValuesBeyondLimit",
       R"({"problem": {"type": "dvi", "f": ["-x1", "-x2", "-x3", "-x4", "-x5"]},
          "x0": [1, 1, 1, 1, 1], "horizon": 1, "output": {"samples": 10000000}})",
       "run input.json", 2, {"output", "6e+07 values", "fewer output.samples"}},
      // --- lcs shapes and values ---------------------------------------------
      {"LcsANotSquare",
       Problem(R"({"type": "lcs", "A": [[0, 1]], "B": [[1]], "C": [[1]], "D": [[1]]})"),
       "run input.json", 2, {"problem.A: is 1x2, expected 1x1"}},
      {"LcsBWrongShape",
       Problem(R"({"type": "lcs", "A": [[0]], "B": [[1, 2]], "C": [[1]], "D": [[1]]})"),
       "run input.json", 2, {"problem.B: is 1x2, expected 1x1"}},
      {"LcsCWrongShape",
       Problem(R"({"type": "lcs", "A": [[0]], "B": [[1]], "C": [[1], [2]], "D": [[1]]})"),
       "run input.json", 2, {"problem.C"}},
      {"LcsDNotSquare",
       Problem(R"({"type": "lcs", "A": [[0]], "B": [[1]], "C": [[1]], "D": [[1, 1]]})"),
       "run input.json", 2, {"problem.D: is 1x2, expected 1x1"}},
      {"LcsAEmpty", Problem(R"({"type": "lcs", "A": [], "B": [], "C": [], "D": []})"),
       "run input.json", 2, {"problem.A: is empty"}},
      {"LcsEntryString",
       Problem(R"({"type": "lcs", "A": [["0"]], "B": [[1]], "C": [[1]], "D": [[1]]})"),
       "run input.json", 2, {"problem.A[0][0]: expected a number"}},
      {"LcsRaggedRows",
       Problem(R"({"type": "lcs", "A": [[0, 1], [1]], "B": [[1], [1]], "C": [[1, 1]],
         "D": [[1]]})",
               "[1, 1]"),
       "run input.json", 2, {"problem.A: row 1 has 1 entries, expected 2"}},
      {"SparseIndexOutOfRange",
       Problem(R"({"type": "lcs", "A": {"sparse": {"rows": 1, "cols": 1, "i": [1], "j": [0],
         "v": [1]}}, "B": [[1]], "C": [[1]], "D": [[1]]})"),
       "run input.json", 2, {"problem.A.sparse.i[0]", "expected an integer in [0, 1)"}},
      {"SparseUnknownField",
       Problem(R"({"type": "lcs", "A": {"sparse": {"rows": 1, "cols": 1, "i": [], "j": [],
         "v": [], "w": []}}, "B": [[1]], "C": [[1]], "D": [[1]]})"),
       "run input.json", 2, {"problem.A.sparse: unknown field \"w\""}},
      {"SparseHugeDimension",
       Problem(R"({"type": "lcs", "A": {"sparse": {"rows": 1000000000, "cols": 1, "i": [],
         "j": [], "v": []}}, "B": [[1]], "C": [[1]], "D": [[1]]})"),
       "run input.json", 2, {"problem.A.sparse.rows", "expected an integer in [0, 10000001)"}},
      {"LcsPWrongLength", Problem(kLcs1 + R"(, "p": [1, 2]})"), "run input.json", 2,
       {"problem.p: has 2 entries, expected 1"}},
      {"LcsUnknownField", Problem(kLcs1 + R"(, "E": [[1]]})"), "run input.json", 2,
       {"problem: unknown field \"E\" for type lcs"}},
      // --- sources and breakpoints (issue 30) ----------------------------------
      {"LcsSourceUsesState", Problem(kLcs1 + R"j(, "q": ["x1 - sin(t)"]})j"), "run input.json", 2,
       {"problem.q", "unknown symbol \"x1\""}},
      {"LcsSourceUnparsable", Problem(kLcs1 + R"(, "p": ["sin(t"]})"), "run input.json", 2,
       {"problem.p", "cannot parse"}},
      {"LcsSourceUnknownParam", Problem(kLcs1 + R"(, "q": ["Vs*t"]})"), "run input.json", 2,
       {"problem.q", "unknown symbol \"Vs\""}},
      {"LcsSourceWrongLength", Problem(kLcs1 + R"(, "p": ["t", "2*t"]})"), "run input.json", 2,
       {"problem.p: has 2 entries, expected 1"}},
      {"LcsSourceWrongEntry", Problem(kLcs1 + R"(, "p": ["t"], "q": [[1]]})"), "run input.json",
       2, {"problem.q[0]", "expected a number"}},
      {"LcsSourceInfiniteAtStart", Problem(kLcs1 + R"j(, "q": ["log(t)"]})j"), "run input.json", 2,
       {"q_source at t = 0", "not finite"}},
      {"BreakpointsOutOfOrder", Problem(kLcs1 + R"(, "breakpoints": [0.5, 0.2]})"),
       "run input.json", 2,
       {"problem.breakpoints[1]: is 0.2, not after problem.breakpoints[0] = 0.5",
        "strictly ascending"}},
      {"BreakpointsNotFinite", Problem(kLcs1 + R"(, "breakpoints": ["1/0"]})"), "run input.json",
       2, {"problem.breakpoints[0]"}},
      {"BreakpointsOutsideHorizon", Problem(kLcs1 + R"(, "breakpoints": [0.5, 2]})"),
       "run input.json", 2, {"problem.breakpoints[1]: is 2, outside (0, horizon] = (0, 1]"}},
      {"BreakpointsNegative", Problem(kLcs1 + R"(, "breakpoints": [-0.5]})"), "run input.json", 2,
       {"problem.breakpoints[0]: is -0.5, outside (0, horizon]"}},
      {"BreakpointsDependOnT", Problem(kLcs1 + R"(, "breakpoints": ["t"]})"), "run input.json", 2,
       {"problem.breakpoints[0]", "depends on t"}},
      {"BreakpointsPeriodZero", Problem(kLcs1 + R"(, "breakpoints": {"period": 0}})"),
       "run input.json", 2, {"problem.breakpoints.period", "a period is positive"}},
      {"BreakpointsTooMany", Problem(kLcs1 + R"(, "breakpoints": {"period": 1e-9}})"),
       "run input.json", 2, {"problem.breakpoints.period", "more than 1000000"}},
      {"BreakpointsNotAList", Problem(kLcs1 + R"(, "breakpoints": 0.5})"), "run input.json", 2,
       {"problem.breakpoints", "expected an array of times"}},
      {"BreakpointsOnPds", Problem(R"({"type": "pds", "A": [[1]], "breakpoints": [0.5]})"),
       "run input.json", 2, {"problem: unknown field \"breakpoints\""}},
      // --- sets --------------------------------------------------------------------
      {"SetUnknownKind", OnSet(R"({"sphere": {}})"), "run input.json", 2,
       {"problem.set", "unknown set kind \"sphere\""}},
      {"BoxEmpty", OnSet(R"({"box": {"lower": [1], "upper": [0]}})"), "run input.json", 2,
       {"problem.set.box", "leave no room"}},
      {"BoxWrongDimension", OnSet(R"({"box": {"lower": [0, 0], "upper": [1, 1]}})"),
       "run input.json", 2, {"problem.set"}},
      {"BallNegativeRadius", OnSet(R"({"ball": {"center": [0], "radius": -1}})"),
       "run input.json", 2, {"problem.set.ball.radius: expected a number ≥ 0"}},
      {"PolyhedronMissingH", OnSet(R"({"polyhedron": {"G": [[1]]}})"), "run input.json", 2,
       {"problem.set.polyhedron: missing field \"h\""}},
      {"PolyhedronRepeatedRow", OnSet(R"({"polyhedron": {"G": [[1], [2]], "h": [1, 2]}})"),
       "run input.json", 2, {"problem.set.polyhedron.G[1]", "repeats the constraint of row 0"}},
      {"PolyhedronEmpty", OnSet(R"({"polyhedron": {"G": [[1], [-1]], "h": [-1, -1]}})"),
       "run input.json", 1, {"K is empty"}},
      {"ProductTwoOrthants", OnSet(R"({"product": ["orthant", "orthant"]})"), "run input.json",
       2, {"problem.set", "a second \"orthant\" part"}},
      {"BoxDviOnBall",
       Problem(R"({"type": "box-dvi", "f": ["u1"], "F": ["u1"], "set": {"ball": {"center": [0],
         "radius": 1}}})"),
       "run input.json", 2, {"problem.set: type box-dvi needs a box"}},
      // --- expressions: crashes and hangs of GiNaC's parser -------------------------
      {"SinWithoutArgument", Dvi("sin()"), "run input.json", 2,
       {"problem.f[0]", "\"sin()\"", "takes 1 argument, got 0"}},
      {"ExpWithoutArgument", Dvi("x1 + exp()"), "run input.json", 2,
       {"problem.f[0]", "\"exp\" takes 1 argument, got 0"}},
      {"LogWithoutArgumentInF", BoxDvi("u1", "log()"), "run input.json", 2,
       {"problem.F[0]", "\"log\" takes 1 argument"}},
      {"TanhWithoutArgument", Dvi("tanh()"), "run input.json", 2, {"\"tanh\" takes 1 argument"}},
      {"AbsWithoutArgumentInF", BoxDvi("u1", "u1 + abs()"), "run input.json", 2,
       {"problem.F[0]", "\"abs\" takes 1 argument"}},
      {"FactorialWithoutArgumentInH", Filippov("factorial()"), "run input.json", 2,
       {"problem.h[0]", "function \"factorial\" is not supported"}},
      {"TanWithoutArgumentInH", Filippov("tan()"), "run input.json", 2,
       {"problem.h[0]", "\"tan\" takes 1 argument"}},
      {"MinOneArgument", Dvi("min(x1)"), "run input.json", 2,
       {"\"min\" takes 2 arguments, got 1"}},
      {"MaxThreeArguments", Dvi("max(1, 2, x1)"), "run input.json", 2,
       {"\"max\" takes 2 arguments, got 3"}},
      {"DenormalParameter", Dvi("-a*x1", R"(, "params": {"a": 5e-324})"), "run input.json", 0,
       {}},
      {"SubnormalParameter", Dvi("-a*x1 + a", R"(, "params": {"a": 1e-310})"), "run input.json",
       0, {}},
      {"ZeroToAVariablePower", Dvi("0^x1"), "run input.json", 2,
       {"problem.f[0]", "\"0^x1\"", "a power of 0 to a variable exponent"}},
      {"SinZeroToThePowerT", Dvi("(sin(0))^t"), "run input.json", 2,
       {"\"(sin(0))^t\"", "a power of 0 to a variable exponent"}},
      {"NegativeToAVariablePower", Dvi("(-2)^x1"), "run input.json", 2,
       {"a power of -2 to a variable exponent"}},
      {"TenToTheTenToTheTen", Dvi("10^(10^10)"), "run input.json", 2,
       {"\"10^(10^10)\"", "is infinite"}},
      {"TwoToTheTenToTheThirty", Dvi("x1 + 2^(10^30)"), "run input.json", 2, {"is infinite"}},
      {"TwoToTheBillion", Dvi("2^(10^9)*x1"), "run input.json", 2, {"is infinite"}},
      {"FactorialHuge", Dvi("factorial(100000000)"), "run input.json", 2,
       {"function \"factorial\" is not supported"}},
      {"BinomialHuge", Dvi("binomial(100000000, 50000000)"), "run input.json", 2,
       {"function \"binomial\" is not supported"}},
      {"Tgamma", Dvi("tgamma(x1)"), "run input.json", 2, {"function \"tgamma\" is not supported"}},
      {"Zeta", Dvi("zeta(1000000)"), "run input.json", 2, {"function \"zeta\" is not supported"}},
      {"NestedExactPowers", Dvi("-((((x1 + x1)^100)^100)^100)"), "run input.json", 1,
       {"not finite"}},
      {"UnknownSymbol", Dvi("x1 + y"), "run input.json", 2,
       {"problem.f[0]: unknown symbol \"y\" (expected t, x1, pi or a parameter)"}},
      {"StateBeyondN", Dvi("x2"), "run input.json", 2, {"unknown symbol \"x2\""}},
      {"MultiplierInPds", Problem(R"({"type": "pds", "F": ["x1 + u1"]})"), "run input.json", 2,
       {"problem.F[0]: unknown symbol \"u1\""}},
      {"DivisionByZero", Dvi("1/0"), "run input.json", 2, {"division by zero"}},
      {"DivisionBySymbolicZero", Dvi("1/(x1 - x1)"), "run input.json", 2, {"division by zero"}},
      {"LogOfZero", Dvi("log(0)"), "run input.json", 2, {"log(0) is infinite"}},
      {"SqrtOfMinusOne", Dvi("sqrt(-1)"), "run input.json", 2,
       {"sqrt(-1) is undefined (not a real number)"}},
      {"NumberBeyondDoubleInExpression", Dvi("1e400*x1"), "run input.json", 2,
       {"the number 1e400 is beyond double precision"}},
      {"MalformedNumber", Dvi("1.e + x1"), "run input.json", 2, {"malformed number \"1.e\""}},
      {"PowerChain", Dvi("x1^2^3"), "run input.json", 2, {"a^b^c is ambiguous"}},
      {"DeepParentheses", Dvi(std::string(300, '(') + "x1" + std::string(300, ')')),
       "run input.json", 2, {"nested deeper than 256 levels"}},
      {"MissingOperator", Dvi("x1 x1"), "run input.json", 2, {"expected an operator"}},
      {"UnbalancedParenthesis", Dvi("(x1 + 1"), "run input.json", 2, {"expected \")\""}},
      {"ParameterReservedName", Dvi("x1", R"(, "params": {"x1": 2})"), "run input.json", 2,
       {"problem.params.x1: the name \"x1\" is reserved"}},
      {"ParameterBadName", Dvi("x1", R"(, "params": {"2k": 2})"), "run input.json", 2,
       {"problem.params.2k: a parameter name must be"}},
      {"ParameterString", Dvi("x1", R"(, "params": {"k": "2"})"), "run input.json", 2,
       {"problem.params.k: expected a number"}},
      {"FNotArray", Problem(R"({"type": "dvi", "f": "x1"})"), "run input.json", 2,
       {"problem.f: expected a non-empty array of expressions"}},
      {"FEmpty", Problem(R"({"type": "dvi", "f": []})"), "run input.json", 2,
       {"problem.f: expected a non-empty array of expressions"}},
      {"TrailingGarbage", BoxDvi("u1", "u1") + "x", "run input.json", 2, {"malformed JSON"}},
      {"ExpressionNotString",
       Problem(R"({"type": "dvi", "f": ["u1"], "F": [{"x": 1}]})"), "run input.json", 2,
       {"problem.F[0]: expected an expression"}},
      {"FilippovF1WrongRows",
       Problem(R"({"type": "filippov", "f0": ["0"], "f1": [["1"], ["1"]], "h": ["x1"]})"),
       "run input.json", 2, {"problem.f1: expected 1 rows"}},
      {"FilippovBothForms",
       Problem(R"({"type": "filippov", "E": [[-1]], "f0": ["0"], "f1": [["1"]], "h": ["x1"]})"),
       "run input.json", 2, {"problem: give either \"E\""}},
      // --- numerical failures: exit 1, nothing written ------------------------------
      // CVODE's dense output overflowed at some of the 501 default sample
      // times, written as rows of inf with exit 0.
      {"HugeStateUnderEventInterpolantOverflows",
       R"({"problem": {"type": "lcs", "A": [[0]], "B": [[-1e6]], "C": [[-1]], "D": [[100]],
          "p": [1e3], "q": [5]}, "x0": [1e300], "horizon": 1e-2, "method": "event"})",
       "run input.json", 1, {"step-failure", "x(0) = ", "not finite", "no files written"}},
      {"HugeStateDiodeBridgeUnderEvent",
       R"({"problem": {"type": "lcs", "A": [[0, -1e6], [100, 0]], "B": [[0, 0, -1e6, 1e6],
          [0, 0, 0, 0]], "C": [[0, 0], [0, 0], [-1, 0], [1, 0]], "D": [[1e-3, 1e-3, -1, 0],
          [1e-3, 1e-3, 0, -1], [1, 0, 0, 0], [0, 1, 0, 0]]}, "x0": [1e300, 1e300],
          "horizon": 1e-4, "method": "event"})",
       "run input.json", 1, {"not finite", "at t = "}},
      // Under auto the failed event-driven interval is stepped over instead.
      {"HugeStateUnderAuto",
       R"({"problem": {"type": "lcs", "A": [[0]], "B": [[-1e6]], "C": [[-1]], "D": [[100]],
          "p": [1e3], "q": [5]}, "x0": [1e300], "horizon": 1e-2})",
       "run input.json", 1, {"uncertified", "time-stepping over [0, 0.01]"}},
      {"GrowthOverflowsUnderStepping",
       R"({"problem": {"type": "lcs", "A": [[1]], "B": [[1]], "C": [[1]], "D": [[1]]},
          "x0": [1e300], "horizon": 100, "method": "stepping"})",
       "run input.json", 1, {"x is not finite"}},
      {"GrowthOverflowsUnderEvent",
       R"({"problem": {"type": "lcs", "A": [[1]], "B": [[1]], "C": [[1]], "D": [[1]]},
          "x0": [1e300], "horizon": 100, "method": "event"})",
       "run input.json", 1, {"step-failure"}},
      {"BlowUpUnderEvent",
       R"({"problem": {"type": "dvi", "f": ["x1^2"]}, "x0": [1], "horizon": 2,
          "method": "event"})",
       "run input.json", 1, {"step-failure", "t = 0.99", "x' is unbounded"}},
      {"BlowUpStepped",
       R"({"problem": {"type": "dvi", "f": ["x1^2"]}, "x0": [1], "horizon": 2,
          "method": "stepping"})",
       "run input.json", 1, {"step-failure", "t = 0.9"}},
      {"RelayChatteringUnderAdaptiveGammaZero",
       R"({"problem": {"type": "filippov", "f0": ["a"], "f1": [["-1"]], "h": ["x1"],
          "params": {"a": 0.5}}, "x0": [1], "horizon": 4, "method": {"name": "stepping",
          "h": 1e-3, "adaptive": true, "gamma": 0}})",
       "run input.json", 1, {"step-size-too-small", "h_min"}},
      // --- resource limits ---------------------------------------------------------
      {"StepsBeyondMaxSteps", Dvi("-x1", "", R"("method": {"name": "stepping", "max_steps": 10})"),
       "run input.json", 2, {"method.h", "1000 steps", "method.max_steps = 10", "raise"}},
      {"TinyHMaxAdaptive",
       Dvi("-x1", "", R"("method": {"name": "stepping", "adaptive": true, "h_max": 1e-300})"),
       "run input.json", 2, {"method.h_max", "raise method.max_steps"}},
      {"TinyHMaxEvent", Dvi("-x1", "", R"("method": {"name": "event", "h_max": 1e-300})"),
       "run input.json", 2, {"method.h_max", "raise method.max_steps"}},
      {"TinyHMaxAuto", Dvi("-x1", "", R"("method": {"h_max": 1e-300})"), "run input.json", 2,
       {"method.h_max"}},
      {"TinyStepOnTheCommandLine", Dvi("-x1"), "run input.json --h 1e-12", 2,
       {"method.h", "1e+12 steps"}},
      {"HorizonNearTheLargestDouble", Valid(R"("x0": [1], "horizon": 1e308)"), "run input.json",
       0, {}},
      {"HorizonNearTheLargestDoubleStepped",
       Valid(R"("x0": [1], "horizon": 1.7e308, "method": "stepping")"), "run input.json", 0, {}},
      {"MaxWallOnTheCommandLine",
       Valid(R"("x0": [1], "horizon": 1e5, "method": {"name": "stepping", "h": 1e-3})"),
       "run input.json --max-wall 0.2", 1, {"max-wall", "0.2 s (--max-wall)", "no files written"}},
      {"MaxWallInTheScene",
       Valid(R"("x0": [1], "horizon": 1e5, "method": {"name": "stepping", "h": 1e-3,
         "max_wall": 0.2})"),
       "run input.json", 1, {"max-wall", "(method.max_wall)"}},
      {"PdsWithManyRepeatedConstraints",
       Problem(R"({"type": "pds", "A": [[1]], "c": [2], "set": {"polyhedron": {"G": [)" +
                   [] {
                     std::string rows = "[1]";
                     for (int k = 1; k < 1001; ++k) rows += ", [1]";
                     return rows;
                   }() + R"(], "h": [)" +
                   [] {
                     std::string h = "1";
                     for (int k = 1; k < 1001; ++k) h += ", 1";
                     return h;
                   }() + "]}}}",
               "[0.5]", R"("method": "auto")"),
       "run input.json", 2, {"problem.set.polyhedron.G[1]", "repeats the constraint of row 0"}},
      // --- command line ------------------------------------------------------------------
      {"NoSubcommand", "", "", 2, {"subcommand"}},
      {"UnknownSubcommand", "", "fly", 2, {"subcommand"}},
      {"RunWithoutScene", "", "run", 2, {"scene is required"}},
      {"RunMissingFile", "", "run missing.json", 2, {"missing.json: cannot open"}},
      {"RunDirectory", "", "run .", 2, {"is a directory"}},
      {"MethodOptionUnknown", Dvi("-x1"), "run input.json --method rk4", 2,
       {"--method: unknown method \"rk4\" (expected auto, stepping, event or bvp)"}},
      {"MethodOptionBvp", Dvi("-x1"), "run input.json --method bvp", 0, {}},
      {"GammaOptionBvp", Boundary("[[1]]", "[[1]]", "[1]"), "run input.json --gamma 0.5", 2,
       {"--gamma", "not used by bvp"}},
      {"StepOptionBvpBeyondMaxSteps", Boundary("[[1]]", "[[1]]", "[1]"),
       "run input.json --h 1e-12", 2, {"method.h", "1e+12 steps", "method.max_steps"}},
      {"StepOptionZero", Dvi("-x1"), "run input.json --h 0", 2, {"--h: expected a step"}},
      {"StepOptionNotANumber", Dvi("-x1"), "run input.json --h abc", 2, {"--h"}},
      {"ThetaOptionTwo", Dvi("-x1"), "run input.json --theta 2", 2, {"--theta", "[0, 1]"}},
      {"GammaOptionNegative", Dvi("-x1"), "run input.json --gamma -0.5", 2, {"--gamma"}},
      {"MaxWallOptionNegative", Dvi("-x1"), "run input.json --max-wall -1", 2,
       {"--max-wall: expected a number of seconds > 0"}},
      {"MaxWallOptionNotANumber", Dvi("-x1"), "run input.json --max-wall soon", 2,
       {"--max-wall"}},
      {"RtolOptionOne", Dvi("-x1"), "run input.json --rtol 1", 2,
       {"--rtol: expected a tolerance in (0, 1), got 1"}},
      {"RtolOptionNaN", Dvi("-x1"), "run input.json --rtol nan", 2,
       {"--rtol: expected a tolerance in (0, 1)"}},
      {"AtolOptionZero", Dvi("-x1"), "run input.json --atol 0", 2,
       {"--atol: expected a tolerance in (0, 1), got 0"}},
      {"AtolOptionNotANumber", Dvi("-x1"), "run input.json --atol tight", 2, {"--atol"}},
      {"HMaxOptionNegative", Dvi("-x1"), "run input.json --h-max -1", 2,
       {"--h-max: expected a step size > 0, got -1"}},
      {"HMaxOptionInfinite", Dvi("-x1"), "run input.json --h-max inf", 2,
       {"--h-max: expected a step size > 0"}},
      {"HMaxOptionBeyondMaxSteps", Dvi("-x1"), "run input.json --method event --h-max 1e-12", 2,
       {"method.h_max", "method.max_steps"}},
      {"RtolOptionBvp", Boundary("[[1]]", "[[1]]", "[1]"), "run input.json --rtol 1e-6", 2,
       {"--rtol", "not used by bvp"}},
      {"OutOptionEmpty", Dvi("-x1"), "run input.json --out ''", 2, {"--out: expected a directory"}},
      {"OutBelowARegularFile", Dvi("-x1"), "run input.json --out input.json/sub", 2,
       {"--out", "cannot create"}},
      {"OutOverTheScene", Dvi("-x1"), "run input.json --out input.json", 2, {"--out"}},
      {"UnknownOption", Dvi("-x1"), "run input.json --fast", 2, {"--fast"}},
      // --- boundary and nash scenes (bvp, issue 32) ---------------------------------------
      {"BoundaryMWrongSize", Boundary("[[1, 0], [0, 1]]", "[[1]]", "[1]"), "run input.json", 2,
       {"boundary.M", "2x2", "expected 1x1"}},
      {"BoundaryBWrongSize", Boundary("[[1]]", "[[1]]", "[1, 2]"), "run input.json", 2,
       {"boundary.b"}},
      {"BoundaryRankDeficient", Boundary("[[0]]", "[[0]]", "[1]"), "run input.json", 2,
       {"boundary", "rank 0 < n = 1"}},
      {"BoundaryNotANumber", Boundary("[[\"abc\"]]", "[[1]]", "[1]"), "run input.json", 2,
       {"boundary.M"}},
      // x(0) + x(T) = 1 in entries near the overflow threshold: M + N
      // overflowed (a crash in the (9.5) diagnostics) before the rows were
      // equilibrated.
      {"BoundaryHugeEntries", Boundary("[[1e308]]", "[[1e308]]", "[1e308]"), "run input.json", 0,
       {}},
      {"BoundaryHugeB", Boundary("[[1e-300]]", "[[1e-300]]", "[1e300]"), "run input.json", 2,
       {"boundary.b[0]", "too large"}},
      {"BoundaryOnPds",
       R"({"problem": {"type": "pds", "F": ["1"], "set": {"box": {"lower": [0], "upper": [1]}}},
          "boundary": {"M": [[1]], "N": [[1]], "b": [1]}, "horizon": 1})",
       "run input.json", 2, {"bvp takes", "not pds"}},
      {"BoundaryStepping", Boundary("[[1]]", "[[1]]", "[1]"), "run input.json --method stepping", 2, {"stepping", "use \"bvp\""}},
      {"BvpStepsBeyondMaxSteps", Boundary("[[1]]", "[[1]]", "[1]", R"(, "max_steps": 50)"),
       "run input.json", 2, {"method.steps", "100 steps", "method.max_steps = 50"}},
      {"BvpStepsHuge",
       R"({"problem": {"type": "dvi", "f": ["-x1"]}, "boundary": {"M": [[1]], "N": [[1]], "b": [1]},
          "horizon": 1, "method": {"name": "bvp", "steps": 1000000000000}})",
       "run input.json", 2, {"method.steps", "1e+12 steps", "method.max_steps"}},
      {"BvpStepTiny",
       R"({"problem": {"type": "dvi", "f": ["-x1"]}, "boundary": {"M": [[1]], "N": [[1]], "b": [1]},
          "horizon": 1, "method": {"name": "bvp", "h": 1e-13}})",
       "run input.json", 2, {"method.h", "steps", "method.max_steps"}},
      {"BvpUnknownsBeyondLimit",
       R"({"problem": {"type": "lcs", "A": [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]],
          "B": [[1], [0], [0], [0]], "C": [[1, 0, 0, 0]], "D": [[1]]},
          "boundary": {"M": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
                       "N": [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]], "b": [1, 1, 1, 1]},
          "horizon": 1, "method": {"name": "bvp", "steps": 4000000}})",
       "run input.json", 2, {"method.steps", "unknowns", "fewer steps"}},
      {"BvpGammaField", Boundary("[[1]]", "[[1]]", "[1]", R"(, "gamma": 0.5)"), "run input.json", 2,
       {"method.gamma", "not used by \"bvp\""}},
      {"BvpStepsAndH", Boundary("[[1]]", "[[1]]", "[1]", R"(, "h": 0.01)"), "run input.json", 2,
       {"method.steps", "not both"}},
      {"BvpSchemeUnknown", Boundary("[[1]]", "[[1]]", "[1]", R"(, "scheme": "7.2")"),
       "run input.json", 2, {"method.scheme", "9.3 or 9.11"}},
      // --- the PETSc back-end (issue 34) -----------------------------------------------------
      {"BvpBackendUnknown", Boundary("[[1]]", "[[1]]", "[1]", R"(, "backend": "cuda")"),
       "run input.json", 2, {"method.backend", "unknown boundary-value backend \"cuda\""}},
      {"BvpBackendNotAString", Boundary("[[1]]", "[[1]]", "[1]", R"(, "backend": 1)"),
       "run input.json", 2, {"method.backend", "expected \"dvi\" or \"petsc\""}},
#ifdef DVI_HOSTILE_PETSC
      {"BvpBackendPetsc", Boundary("[[1]]", "[[1]]", "[1]", R"(, "backend": "petsc")"),
       "run input.json", 0, {}},
      {"BvpBackendPetscOnABall",
       R"({"problem": {"type": "dvi", "f": ["-x1 + u1"], "F": ["u1 - x1"],
          "set": {"ball": {"center": [0], "radius": 1}}},
          "boundary": {"M": [[1]], "N": [[0]], "b": [1]}, "horizon": 1,
          "method": {"name": "bvp", "steps": 100, "backend": "petsc"}})",
       "run input.json", 2, {"method.backend", "not one with a ball"}},
#else
      {"BvpBackendPetscWithoutPetsc", Boundary("[[1]]", "[[1]]", "[1]", R"(, "backend": "petsc")"),
       "run input.json", 2, {"method.backend", "built without PETSc"}},
#endif
      {"BvpMaxWall", Boundary("[[1]]", "[[1]]", "[1]", R"(, "max_wall": 60)"), "run input.json", 0,
       {}},
      // x' = u, 0 <= u ⊥ 1 >= 0 forces u = 0, so x(0) - x(T) = 1 has no
      // solution: Newton fails on the aggregate VI.
      {"BvpUnsolvable",
       R"({"problem": {"type": "lcs", "A": [[0]], "B": [[1]], "C": [[0]], "D": [[0]], "q": [1]},
          "boundary": {"M": [[1]], "N": [[-1]], "b": [1]}, "horizon": 1,
          "method": {"name": "bvp", "steps": 100}})",
       "run input.json", 1, {"step-failure", "100 steps", "iteration", "residual", "no files written"}},
      {"NashWithX0", Nash(R"("S": [[[1]]])", R"(, "x0": [1])"), "run input.json", 2,
       {"x0", "problem.players"}},
      {"NashBlockWrongSize", Nash(R"("P": [[[1, 0]]])"), "run input.json", 2,
       {"problem.players[0].P[0]", "1x2", "expected 1x1"}},
      {"NashBlockListTooShort", Nash(R"("P": [])"), "run input.json", 2,
       {"problem.players[0].P", "a list of 1 matrices"}},
      {"NashHWrongRows", R"({"problem": {"type": "nash", "players": [{"x0": [1], "G": [[-1]],
          "H": [[1], [1]]}]}, "horizon": 1})",
       "run input.json", 2, {"problem.players[0].H", "2x1"}},
      {"NashUnknownField", Nash(R"("Z": 1)"), "run input.json", 2,
       {"problem.players[0]", "\"Z\""}},
      {"NashTheta", Nash(R"("S": [[[1]]])", R"(, "method": {"name": "bvp", "theta": 0.5})"),
       "run input.json", 2, {"method.theta", "nash"}},
      // S = -1 makes Xi^0 of (10.2) indefinite: Prop. 10.1 does not hold.
      // The run goes on (the discrete (4.5) may still be solvable) with a
      // warning, and summary.json records the check.
      {"NashXiNotPsd", Nash(R"("S": [[[-1]]], "U": {"box": {"lower": [-1], "upper": [1]}})"),
       "run input.json", 0, {"warning", "Prop. 10.1"}},
      // --- dvisim solve ---------------------------------------------------------------------
      {"SolveOutOverTheProblem",
       R"({"problem": {"type": "lcp", "M": [[2, 1], [1, 2]], "q": [-1, -1]}})",
       "solve input.json --out input.json", 2, {"is the problem file itself"}},
      {"SolveMissingFile", "", "solve missing.json", 2, {"missing.json: cannot open"}},
      {"SolveUnknownType", R"({"problem": {"type": "qp"}})", "solve input.json", 2,
       {"problem.type", "\"qp\""}},
      {"SolveMatrixNotSquare", R"({"problem": {"type": "lcp", "M": [[2, 1]], "q": [-1]}})",
       "solve input.json", 2, {"problem.M"}},
      {"SolveToleranceTwo", R"({"problem": {"type": "lcp", "M": [[2]], "q": [-1]}})",
       "solve input.json --tol 2", 2, {"--tol"}},
      {"SolveSolverUnknown", R"({"problem": {"type": "lcp", "M": [[2]], "q": [-1]}})",
       "solve input.json --solver magic", 2, {"--solver", "magic"}},
      {"SolveRepeatedConstraint",
       R"({"problem": {"type": "avi", "M": [[1]], "q": [0], "set": {"polyhedron":
          {"G": [[1], [1]], "h": [1, 1]}}}})",
       "solve input.json", 2, {"problem.set.polyhedron.G[1]", "repeats the constraint of row 0"}},
      {"SolveHugeEntries", R"({"problem": {"type": "lcp", "M": [[1e308]], "q": [-1e308]}})",
       "solve input.json", 0, {}},
      // --- dvisim sweep (issue 34): the sweep file's mistakes -----------------
      {"SweepEmptyFile", "", "sweep input.json --out o", 2, {"malformed JSON"}},
      {"SweepNotAnObject", "[1]", "sweep input.json --out o", 2, {"sweep: expected an object"}},
      {"SweepSceneFileMissing", R"({"scene": "nowhere.json"})", "sweep input.json --out o", 2,
       {"nowhere.json", "cannot open"}},
      {"SweepSceneNotAScene", R"({"scene": 3})", "sweep input.json --out o", 2,
       {"sweep.scene: expected a scene file name or a scene object"}},
      {"SweepBaseSceneInvalid", R"({"scene": {"problem": {"type": "dvi", "f": ["-x1"]}}})",
       "sweep input.json --out o", 2, {"sweep.scene: ", "x0"}},
      {"SweepPointerNotAPointer",
       R"({"scene": )" + Dvi("-x1") + R"(, "grid": {"x0": [1]}})", "sweep input.json --out o", 2,
       {"sweep.grid[\"x0\"]", "JSON pointer"}},
      {"SweepPointerBeyondArray",
       R"({"scene": )" + Dvi("-x1") + R"(, "grid": {"/x0/4": [1]}})", "sweep input.json --out o",
       2, {"member 0: /x0/4", "has 1 entries"}},
      {"SweepValuesNotAList",
       R"({"scene": )" + Dvi("-x1") + R"(, "grid": {"/x0/0": 1}})", "sweep input.json --out o", 2,
       {"sweep.grid[\"/x0/0\"]", "non-empty list"}},
      {"SweepOutIsTheRunFolder", R"({"scene": )" + Dvi("-x1") + "}", "sweep input.json --out .",
       2, {"--out", "exists"}},
      {"SweepMemberMaxWallRefusedAsARow",
       R"({"scene": )" + Dvi("-x1") + R"(, "members": [{"/method": {"name": "stepping",
          "max_wall": 1}}]})",
       "sweep input.json --out o", 0, {}},
  };
  return cases;
}

// The files and directories under root, relative, sorted.
std::set<std::string> Listing(const fs::path& root) {
  std::set<std::string> names;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root))
    names.insert(fs::relative(entry.path(), root).string());
  return names;
}

std::string Slurp(const fs::path& path) {
  std::ifstream stream(path);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

// Every field of a CSV after its header is a finite number, and there are rows.
void ExpectFiniteCsv(const std::string& csv) {
  std::istringstream lines(csv);
  std::string line;
  ASSERT_TRUE(std::getline(lines, line)) << "empty trajectory.csv";
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      ASSERT_TRUE(end != field.c_str() && *end == '\0' && std::isfinite(value))
          << "row " << rows << ": \"" << field << "\" is not a finite number";
    }
  }
  EXPECT_GE(rows, 2);
}

class HostileInput : public ::testing::TestWithParam<HostileCase> {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("dvisim_hostile_" + std::to_string(::getpid()) + "_" + GetParam().name);
    fs::remove_all(directory_);
    fs::create_directories(directory_ / "run");
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path directory_;
};

TEST_P(HostileInput, AnsweredWithAResultOrAClearErrorAndNoStrayFiles) {
  const HostileCase& c = GetParam();
  const fs::path run = directory_ / "run";
  const std::string executable = std::getenv("DVISIM_UNDER_TEST") != nullptr
                                     ? std::getenv("DVISIM_UNDER_TEST")
                                     : DVISIM_EXECUTABLE;
  if (!c.input.empty() || c.args.find("input.json") != std::string::npos)
    std::ofstream(run / "input.json", std::ios::binary) << c.input;
  const std::set<std::string> before = Listing(run);
  const fs::path out = directory_ / "stdout.txt";
  const fs::path err = directory_ / "stderr.txt";
  // The shell runs dvisim in `run`, so that default outputs (out/<name>)
  // land there, under timeout(1), which ends a hang with 124.
  const std::string command = "cd '" + run.string() + "' && timeout -k 5 " +
                              std::to_string(kHangSeconds) + " '" + executable + "' " + c.args +
                              " >'" + out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "the shell did not exit";
  const int code = WEXITSTATUS(status);
  const std::string message = Slurp(err);
  ASSERT_NE(code, 124) << "dvisim hung (killed after " << kHangSeconds << " s)";
  ASSERT_TRUE(code == 0 || code == 1 || code == 2)
      << "dvisim crashed (exit " << code << "): " << message;
  EXPECT_EQ(code, c.exit_code) << "stderr: " << message << "\nstdout: " << Slurp(out);
  for (const std::string& word : c.words)
    EXPECT_NE(message.find(word), std::string::npos)
        << "the message lacks \"" << word << "\": " << message;
  if (code != 0) {
    EXPECT_FALSE(message.empty()) << "a failure without a message";
    EXPECT_EQ(Listing(run), before) << "files left behind by a failed run";
    return;
  }
  if (c.args.rfind("run", 0) != 0) return;
  // Success: complete, finite output in the default directory out/scene.
  const fs::path dir = run / "out" / "scene";
  ASSERT_TRUE(fs::exists(dir / "summary.json")) << "no summary.json";
  EXPECT_NE(Slurp(dir / "summary.json").find("\"status\": \"success\""), std::string::npos);
  ExpectFiniteCsv(Slurp(dir / "trajectory.csv"));
}

INSTANTIATE_TEST_SUITE_P(Table, HostileInput, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<HostileCase>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
