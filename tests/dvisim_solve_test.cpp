// SPDX-License-Identifier: Apache-2.0
// `dvisim solve`: the problem-file reader (src/dvisim/problem_file) and
// end-to-end runs of the built binary on examples/problems and on bad files.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "problem_file.hpp"
#include "support/dvisim_fixture.hpp"

namespace dvi::dvisim {
namespace {

namespace fs = std::filesystem;
using testing::RunOutcome;

constexpr double kInf = std::numeric_limits<double>::infinity();
// dvisim solves at the default tolerance 1e-10 unless told otherwise.
constexpr double kResidualTolerance = 1e-10;
// The example problems are well conditioned (condition numbers below 10), so
// z is within 10 × the residual of the exact solution.
constexpr double kSolutionTolerance = 1e-9;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The message ParseProblemFile throws for `text`, or "" when it parses.
std::string ParseError(const std::string& text) {
  try {
    ParseProblemFile(text);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ProblemFile, ReadsDenseLcp) {
  const ProblemFile file = ParseProblemFile(
      R"({"name": "x", "problem": {"type": "lcp", "M": [[2, 1], [0, 3]], "q": [-1, 2]}})");
  EXPECT_EQ(file.name, "x");
  EXPECT_EQ(file.type, ProblemType::kLcp);
  ASSERT_FALSE(file.M.is_sparse);
  EXPECT_EQ(file.M.dense, (Eigen::Matrix2d() << 2, 1, 0, 3).finished());
  EXPECT_EQ(file.q(0), -1.0);
  EXPECT_FALSE(file.solver.has_value());
  EXPECT_FALSE(file.tolerance.has_value());
}

TEST(ProblemFile, RejectsInfiniteQ) {
  EXPECT_EQ(ParseError(R"({"problem": {"type": "lcp", "M": [[1]], "q": ["-inf"]}})"),
            "problem.q[0]: expected a finite number, got \"-inf\"");
}

TEST(ProblemFile, ReadsMcpWithInfiniteBoundsAndOptions) {
  const ProblemFile file = ParseProblemFile(R"({
    "problem": {"type": "mcp", "M": [[1, 0], [0, 1]], "q": [0, 0],
                "lower": ["-inf", 0], "upper": ["inf", 2], "tol": 1e-8},
    "solver": "newton"})");
  EXPECT_EQ(file.type, ProblemType::kMcp);
  EXPECT_EQ(file.lower, Eigen::Vector2d(-kInf, 0));
  EXPECT_EQ(file.upper, Eigen::Vector2d(kInf, 2));
  EXPECT_EQ(file.solver, SolverMethod::kNewton);
  EXPECT_EQ(file.tolerance, 1e-8);
}

TEST(ProblemFile, ReadsSparseMatrixSummingDuplicates) {
  const ProblemFile file = ParseProblemFile(R"({"problem": {"type": "lcp",
    "M": {"sparse": {"rows": 2, "cols": 2, "i": [0, 1, 0], "j": [0, 1, 0], "v": [1, 4, 2]}},
    "q": [1, 1]}})");
  ASSERT_TRUE(file.M.is_sparse);
  EXPECT_EQ(file.M.ToDense(), (Eigen::Matrix2d() << 3, 0, 0, 4).finished());
}

TEST(ProblemFile, ReadsEverySetKind) {
  // An avi with M = I of order m and q = 0 on `set`.
  const auto set_of = [](const std::string& set, int m) {
    nlohmann::json M = nlohmann::json::array();
    for (int i = 0; i < m; ++i) {
      M.push_back(std::vector<double>(static_cast<std::size_t>(m), 0.0));
      M[static_cast<std::size_t>(i)][static_cast<std::size_t>(i)] = 1.0;
    }
    const nlohmann::json root = {
        {"problem",
         {{"type", "avi"}, {"M", M}, {"q", std::vector<double>(static_cast<std::size_t>(m), 0.0)},
          {"set", nlohmann::json::parse(set)}}}};
    return ParseProblemFile(root.dump()).set;
  };
  EXPECT_EQ(set_of(R"("orthant")", 1).kind(), ConvexSet::Kind::kOrthant);
  EXPECT_EQ(set_of(R"({"box": {"lower": [0, "-inf"], "upper": [1, "inf"]}})", 2).kind(),
            ConvexSet::Kind::kBox);
  const ConvexSet polyhedron = set_of(R"({"polyhedron": {"G": [[1, 1]], "h": [1]}})", 2);
  EXPECT_EQ(polyhedron.kind(), ConvexSet::Kind::kPolyhedron);
  EXPECT_TRUE(polyhedron.Contains(Eigen::Vector2d(0.5, 0.5)));
  EXPECT_FALSE(polyhedron.Contains(Eigen::Vector2d(1.0, 0.5)));
  const ConvexSet ball = set_of(R"({"ball": {"center": [1, 0], "radius": 2}})", 2);
  EXPECT_EQ(ball.kind(), ConvexSet::Kind::kBall);
  EXPECT_EQ(ball.radius(), 2.0);
  const ConvexSet product =
      set_of(R"({"product": ["orthant", {"ball": {"center": [0, 0], "radius": 1}}]})", 3);
  ASSERT_EQ(product.kind(), ConvexSet::Kind::kProduct);
  ASSERT_EQ(product.parts().size(), 2u);
  EXPECT_EQ(product.parts()[0].dim(), 1);
  EXPECT_EQ(product.parts()[1].dim(), 2);
}

TEST(ProblemFile, EachBadInputHasItsMessage) {
  const std::string lcp_head = R"({"problem": {"type": "lcp", )";
  const std::string avi_head = R"({"problem": {"type": "avi", "M": [[1, 0], [0, 1]], "q": [0, 0], )";
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"{\n  \"problem\": {\n    \"type\" \"lcp\"}}", "malformed JSON at line 3, column 16: syntax error while parsing object separator"},
      {"[1, 2]", "(file): expected a JSON object, got [1,2]"},
      {R"({"problem": {"type": "lcp", "M": [[1]], "q": [0]}, "color": 1})",
       "(file): unknown field \"color\""},
      {R"({"solver": "auto"})", "(file): missing field \"problem\""},
      {R"({"problem": {"M": [[1]]}})", "problem: missing field \"type\""},
      {R"({"problem": {"type": "qp"}})", "problem.type: expected \"lcp\", \"mcp\" or \"avi\", got \"qp\""},
      {lcp_head + R"("M": [[1, 2, 3, 4], [1, 2, 3, 4], [1, 2, 3], [1, 2, 3, 4]], "q": [0, 0, 0, 0]}})",
       "problem.M: row 2 has 3 entries, expected 4"},
      {lcp_head + R"("M": [[1, 0], [0, 1]], "q": [0, "abc"]}})",
       "problem.q[1]: expected a number, got \"abc\""},
      {lcp_head + R"("M": [[1, "inf"], [0, 1]], "q": [0, 0]}})",
       "problem.M[0][1]: expected a finite number, got \"inf\""},
      {lcp_head + R"("M": [[1, 0], 3], "q": [0, 0]}})",
       "problem.M[1]: expected an array (a row), got 3"},
      {lcp_head + R"("M": [[1, 0, 0], [0, 1, 0]], "q": [0, 0]}})",
       "problem.M: is 2x3, expected a square matrix"},
      {lcp_head + R"("M": [[1, 0], [0, 1]], "q": [0, 0, 0]}})",
       "problem.q: has 3 entries, expected 2"},
      {lcp_head + R"("M": [[1, 0], [0, 1]]}})", "problem: missing field \"q\""},
      {lcp_head + R"("M": [[1]], "q": [0], "lower": [0]}})",
       "problem: unknown field \"lower\" for type lcp"},
      {lcp_head + R"("M": {"sparse": {"rows": 2, "cols": 2, "i": [0, 5], "j": [0, 1], "v": [1, 1]}}, "q": [0, 0]}})",
       "problem.M.sparse.i[1]: expected an integer in [0, 2), got 5"},
      {lcp_head + R"("M": {"sparse": {"rows": 2, "cols": 2, "i": [0], "j": [0, 1], "v": [1, 1]}}, "q": [0, 0]}})",
       "problem.M.sparse.i: expected an array of 2 indices (as many as v), got [0]"},
      {lcp_head + R"("M": [[1]], "q": [0]}, "solver": "simplex"})", "solver: "},
      {lcp_head + R"("M": [[1]], "q": [0], "tol": 2}})",
       "problem.tol: expected a tolerance in (0, 1), got 2"},
      {lcp_head + R"("M": [[1]], "q": [0], "tol": 1e-6}, "tol": 1e-6})",
       "problem.tol: given both here and at the top level"},
      {R"({"problem": {"type": "mcp", "M": [[1, 0], [0, 1]], "q": [0, 0], "lower": [0, 2], "upper": [1, 1]}})",
       "problem.lower[1]: 2.0 is above upper[1] = 1.0"},
      {R"({"problem": {"type": "mcp", "M": [[1]], "q": [0], "lower": ["inf"], "upper": ["inf"]}})",
       "problem.lower[0]: must be below \"inf\""},
      {R"({"problem": {"type": "mcp", "M": [[1]], "q": [0], "lowr": [0], "upper": [1]}})",
       "problem: unknown field \"lowr\" for type mcp"},
      {avi_head + R"("set": "cube"}})", "problem.set: unknown set \"cube\""},
      {avi_head + R"("set": {"box": {"lower": [0, 0, 0], "upper": [1, 1, 1]}}}})",
       "problem.set: has dimension 3, expected 2"},
      {avi_head + R"("set": {"box": {"lower": [0, 2], "upper": [1, 1]}}}})",
       "problem.set.box: lower[1] = 2.0 and upper[1] = 1.0 leave no room"},
      {avi_head + R"("set": {"ball": {"center": [0, 0], "radius": -1}}}})",
       "problem.set.ball.radius: expected a number ≥ 0, got -1.0"},
      {avi_head + R"("set": {"polyhedron": {"G": [[1, 1]]}}}})",
       "problem.set.polyhedron: missing field \"h\" (G has rows)"},
      {avi_head + R"("set": {"product": ["orthant", "orthant"]}}})",
       "problem.set.product[1]: a second \"orthant\" part"},
      {avi_head + R"("set": {"cone": {}}}})", "problem.set: unknown set kind \"cone\""},
  };
  for (const Case& c : cases) {
    const std::string message = ParseError(c.text);
    EXPECT_TRUE(Contains(message, c.message))
        << "input: " << c.text << "\nmessage:  " << message << "\nexpected: " << c.message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

class DvisimBinary : public testing::DvisimBinaryTest {
 protected:
  static std::string Example(const std::string& name) {
    return std::string(DVI_EXAMPLES_DIR) + "/problems/" + name;
  }
};

Eigen::VectorXd VectorOf(const nlohmann::json& array) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(array.size()));
  for (std::size_t i = 0; i < array.size(); ++i) v(static_cast<Eigen::Index>(i)) = array[i].get<double>();
  return v;
}

TEST_F(DvisimBinary, SolvesEveryExample) {
  struct Example {
    std::string file;
    std::string method;
    Eigen::VectorXd z;  // Empty: not known in closed form.
    bool has_index_sets;
  };
  // avi_ball: on the unit circle M z + q = −λ z, i.e. z = −(M + λI)⁻¹ q; with
  // a = 1 + λ, M + λI is √(a² + ¼) times a rotation, so ‖z‖ = 5/√(a² + ¼) = 1
  // gives a = √24.75 and z = (3a − 2, 4a + 1.5)/25.
  const double a = std::sqrt(24.75);
  const std::vector<Example> examples = {
      {"lcp_p_matrix.json", "newton", Eigen::Vector3d(0.5, 0, 1), true},
      {"mcp_infinite_bounds.json", "newton", Eigen::Vector3d(1.25, 0, -1), true},
      {"avi_ball.json", "kkt", Eigen::Vector2d(3 * a - 2, 4 * a + 1.5) / 25, false},
      {"avi_polyhedron.json", "kkt", Eigen::Vector3d(0.5, 0.5, 0.25), false},
  };
  for (const Example& example : examples) {
    const RunOutcome run = Dvisim("solve '" + DvisimBinary::Example(example.file) + "'");
    ASSERT_EQ(run.exit_code, 0) << example.file << ": " << run.err << run.out;
    EXPECT_EQ(run.err, "");
    const nlohmann::json answer = nlohmann::json::parse(run.out);
    EXPECT_EQ(answer["status"], "solved") << example.file;
    EXPECT_EQ(answer["method"], example.method) << example.file;
    EXPECT_LE(answer["residual"].get<double>(), kResidualTolerance) << example.file;
    for (const char* field : {"message", "z", "w", "iterations", "seconds"})
      EXPECT_TRUE(answer.contains(field)) << example.file << " lacks " << field;
    EXPECT_EQ(answer.contains("alpha") && answer.contains("beta") && answer.contains("gamma"),
              example.has_index_sets)
        << example.file;
    if (example.z.size() > 0) {
      EXPECT_LE((VectorOf(answer["z"]) - example.z).cwiseAbs().maxCoeff(), kSolutionTolerance)
          << example.file;
    }
  }
}

TEST_F(DvisimBinary, BallExampleSatisfiesTheVi) {
  // On the unit circle, z solves the VI iff −w = −(Mz + q) is an outward
  // normal: −w = λ z with λ ≥ 0.
  const RunOutcome run = Dvisim("solve '" + Example("avi_ball.json") + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json answer = nlohmann::json::parse(run.out);
  const Eigen::Vector2d z = VectorOf(answer["z"]);
  const Eigen::Vector2d w = VectorOf(answer["w"]);
  // Newton on the KKT system stops below the residual tolerance 1e-10
  // (measured: 1e-12, after 7 steps); the normal's direction is accurate to
  // about that times ‖w‖ ≈ 4.
  constexpr double kDirectionTolerance = 1e-10;
  EXPECT_NEAR(z.norm(), 1.0, kDirectionTolerance);
  EXPECT_NEAR(z.x() * w.y() - z.y() * w.x(), 0.0, kDirectionTolerance);
  EXPECT_LT(z.dot(w), 0.0);
}

TEST_F(DvisimBinary, OptionsOverrideTheFile) {
  const RunOutcome run = Dvisim("solve '" + Example("lcp_p_matrix.json") + "' --solver lemke --tol 1e-12");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json answer = nlohmann::json::parse(run.out);
  EXPECT_EQ(answer["method"], "lemke");
  EXPECT_LE(answer["residual"].get<double>(), 1e-12);
}

TEST_F(DvisimBinary, OutWritesTheAnswerFileOnly) {
  const std::string out = Path("answer.json");
  const RunOutcome run = Dvisim("solve '" + Example("mcp_infinite_bounds.json") + "' --out '" + out + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, "");
  const nlohmann::json answer = nlohmann::json::parse(Slurp(out));
  EXPECT_EQ(answer["status"], "solved");
  for (const auto& entry : fs::directory_iterator(Path("")))
    EXPECT_FALSE(Contains(entry.path().filename().string(), ".tmp-")) << entry.path();
}

TEST_F(DvisimBinary, InfeasibleExitsOneWithCertificate) {
  // Rows sum to −2 ≥ 0: no feasible z (M positive semidefinite).
  const std::string problem = Write(
      "infeasible.json", R"({"problem": {"type": "lcp", "M": [[1, -1], [-1, 1]], "q": [-1, -1]}})");
  const std::string out = Path("answer.json");
  const RunOutcome run = Dvisim("solve '" + problem + "' --out '" + out + "'");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  const nlohmann::json answer = nlohmann::json::parse(Slurp(out));
  EXPECT_EQ(answer["status"], "infeasible");
  ASSERT_TRUE(answer.contains("certificate"));
  const Eigen::Vector2d y = VectorOf(answer["certificate"]);
  EXPECT_GE(y.minCoeff(), 0.0);
  EXPECT_LT(-y.sum(), 0.0);  // qᵀy < 0
}

TEST_F(DvisimBinary, BadInputExitsTwoWithOneLineAndNoOutFile) {
  struct Case {
    std::string arguments;
    std::string message;
  };
  const std::string bad_row = Write(
      "bad_row.json",
      R"({"problem": {"type": "lcp", "M": [[1, 0, 0], [0, 1], [0, 0, 1]], "q": [0, 0, 0]}})");
  const std::string malformed = Write("malformed.json", "{\n  \"problem\": [1,\n}");
  const std::string out = Path("answer.json");
  const std::vector<Case> cases = {
      {"solve '" + bad_row + "'", bad_row + ": problem.M: row 1 has 2 entries, expected 3"},
      {"solve '" + malformed + "'", malformed + ": malformed JSON at line 3, column 1: "},
      {"solve '" + Path("missing.json") + "'", Path("missing.json") + ": cannot open"},
      {"solve '" + Example("mcp_infinite_bounds.json") + "' --solver lemke",
       "solver method 'lemke' does not apply to a box MCP"},
      {"solve '" + Example("lcp_p_matrix.json") + "' --solver simplex", "--solver: "},
      {"solve '" + Example("lcp_p_matrix.json") + "' --tol 2",
       "--tol: expected a tolerance in (0, 1), got 2"},
  };
  for (const Case& c : cases) {
    const RunOutcome run = Dvisim(c.arguments + " --out '" + out + "'");
    EXPECT_EQ(run.exit_code, 2) << c.arguments;
    EXPECT_TRUE(Contains(run.err, c.message)) << c.arguments << "\nstderr: " << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_FALSE(fs::exists(out)) << c.arguments;
  }
}

TEST_F(DvisimBinary, UsageMistakesExitTwo) {
  EXPECT_EQ(Dvisim("").exit_code, 2);
  EXPECT_EQ(Dvisim("simulate x.json").exit_code, 2);
  EXPECT_EQ(Dvisim("solve").exit_code, 2);
  EXPECT_EQ(Dvisim("solve '" + Example("lcp_p_matrix.json") + "' --tol abc").exit_code, 2);
  EXPECT_EQ(Dvisim("--help").exit_code, 0);
}

}  // namespace
}  // namespace dvi::dvisim
