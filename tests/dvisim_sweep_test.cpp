// SPDX-License-Identifier: Apache-2.0
// Issue 34's `dvisim sweep` on one process: the member product, overrides,
// rows for members that fail, and the sweep file's mistakes refused before
// anything runs (the 2-rank run: tests/mpi/sweep_ranks.sh; hostile files:
// hostile_input_test's Sweep rows).
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "json_reading.hpp"
#include "sweep_command.hpp"
#include "sweep_file.hpp"

namespace dvi::dvisim {
namespace {

namespace fs = std::filesystem;

// x' = −sgn(x) + a from x0 (the Filippov relay): x(T) = max(0, x0 − (1 − a)T).
const std::string kRelay =
    R"({"problem": {"type": "filippov", "f0": ["a"], "f1": [["-1"]], "h": ["x1"],
        "params": {"a": 0.5}}, "x0": [1], "horizon": 4,
        "method": {"name": "event", "rtol": 1e-10}, "output": {"samples": 5}})";

std::string SweepText(const std::string& rest) {
  return R"({"scene": )" + kRelay + (rest.empty() ? "" : ", " + rest) + "}";
}

TEST(SweepFile, MembersAreTheListTimesTheGridFirstKeySlowest) {
  const Sweep sweep = ParseSweep(
      SweepText(R"("members": [{"/method/rtol": 1e-8}, {"/method/rtol": 1e-9}],
                   "grid": {"/problem/params/a": [0.1, 0.2, 0.3], "/x0/0": [1, 2]})"),
      "sweep.json");
  ASSERT_EQ(sweep.members.size(), 12u);
  EXPECT_EQ(sweep.columns,
            (std::vector<std::string>{"/method/rtol", "/problem/params/a", "/x0/0"}));
  // Member 7 = list entry 1, grid point 1 = (a index 0, x0 index 1).
  const nlohmann::json scene = MemberScene(sweep, 7);
  EXPECT_EQ(scene["method"]["rtol"], 1e-9);
  EXPECT_EQ(scene["problem"]["params"]["a"], 0.1);
  EXPECT_EQ(scene["x0"][0], 2);
  // Member 4: list entry 0, a index 2, x0 index 0.
  EXPECT_EQ(MemberScene(sweep, 4)["problem"]["params"]["a"], 0.3);
  EXPECT_EQ(MemberScene(sweep, 4)["x0"][0], 1);
  EXPECT_EQ(sweep.out_dir, "out/sweep");
  EXPECT_FALSE(sweep.trajectories);
}

TEST(SweepFile, MistakesAreRefusedNamingTheField) {
  const auto message = [](const std::string& text) {
    try {
      (void)ParseSweep(text, "sweep.json");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(SweepText(R"("grid": {"x0/0": [1]})")),
            "sweep.grid[\"x0/0\"]: expected a JSON pointer into the scene such as \"/x0/0\" or "
            "\"/problem/params/a\", got \"x0/0\"");
  EXPECT_EQ(message(SweepText(R"("grid": {"/x0/0": []})")),
            "sweep.grid[\"/x0/0\"]: expected a non-empty list of values, got []");
  EXPECT_EQ(message(SweepText(R"("grid": {"/x0/3": [1]})")),
            "sweep: member 0: /x0/3: \"/x0\" has 1 entries, no index 3");
  EXPECT_EQ(message(SweepText(R"("grid": {"/method/ode/x": [1]})")),
            "sweep: member 0: /method/ode/x: \"/method/ode\" is not in the scene");
  EXPECT_EQ(message(SweepText(R"("members": [{"/x0/0": 1}, 3])")),
            "sweep.members[1]: expected an object of overrides {\"/pointer\": value}, got 3");
  EXPECT_EQ(message(SweepText(R"("grids": {})")),
            "sweep.grids: unknown field (expected scene, grid, members, output, description)");
  EXPECT_EQ(message(R"({"grid": {"/x0/0": [1]}})"), "sweep: missing field \"scene\"");
  EXPECT_EQ(message(SweepText(R"("output": {"trajectories": "yes"})")),
            "sweep.output.trajectories: expected true or false, got \"yes\"");
  // 1001 × 1000 members: refused before a single scene is built.
  std::string values = "[0";
  for (int k = 1; k < 1001; ++k) values += "," + std::to_string(k);
  const std::string big = SweepText(R"("grid": {"/x0/0": )" + values + R"(], "/horizon": )" +
                                    values.substr(0, values.rfind(',')) + "]}");
  EXPECT_EQ(message(big), "sweep: more than 1000000 members (the grid's sizes times the "
                          "members' count)");
}

class SweepRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dvi_sweep_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  int Run(const std::string& sweep_text, bool trajectories = false) {
    std::ofstream(dir_ / "sweep.json") << sweep_text;
    SweepCommand command;
    command.sweep_path = (dir_ / "sweep.json").string();
    command.out_dir = (dir_ / "out").string();
    command.trajectories = trajectories;
    return RunSweepCommand(command, out_, err_);
  }
  std::vector<std::string> Rows() const {
    std::ifstream csv(dir_ / "out" / "sweep.csv");
    std::vector<std::string> rows;
    for (std::string line; std::getline(csv, line);) rows.push_back(line);
    return rows;
  }

  fs::path dir_;
  std::ostringstream out_, err_;
};

TEST_F(SweepRun, EveryMemberIsARowWithItsExactFinalState) {
  ASSERT_EQ(Run(SweepText(R"("grid": {"/problem/params/a": [0.25, 0.75], "/x0/0": [1, 2]})"),
                true),
            0)
      << err_.str();
  const std::vector<std::string> rows = Rows();
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0],
            "member,/problem/params/a,/x0/0,status,message,t_final,x1,events,steps,rhs_evals,"
            "certified,wall_seconds");
  // x(4) = max(0, x0 − (1 − a)·4): 0, 0, 0, 1.
  const double exact[] = {0, 0, 0, 1};
  for (int k = 0; k < 4; ++k) {
    std::istringstream row(rows[static_cast<std::size_t>(k) + 1]);
    std::vector<std::string> fields;
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    ASSERT_EQ(fields.size(), 12u) << rows[static_cast<std::size_t>(k) + 1];
    EXPECT_EQ(fields[0], std::to_string(k));
    EXPECT_EQ(fields[3], "success");
    EXPECT_EQ(fields[5], "4");
    EXPECT_NEAR(std::stod(fields[6]), exact[k], 1e-9) << "member " << k;
    EXPECT_EQ(fields[10], "true");
    EXPECT_TRUE(fs::exists(dir_ / "out" / "members" / std::to_string(k) / "trajectory.csv"));
    EXPECT_TRUE(fs::exists(dir_ / "out" / "members" / std::to_string(k) / "summary.json"));
  }
  EXPECT_NE(out_.str().find("4 members on 1 rank(s), 4 succeeded, 0 failed"), std::string::npos)
      << out_.str();
}

TEST_F(SweepRun, AMemberThatIsRefusedOrFailsIsARowAndTheSweepGoesOn) {
  // Member 1: x0 of the wrong size (refused by the scene); member 2: a step
  // limit the run reaches (a failed run); member 3: a wall-clock budget,
  // which would end every member's process (refused).
  ASSERT_EQ(Run(SweepText(R"("members": [{}, {"/x0": [1, 2]}, {"/method/max_steps": 1},
                                         {"/method/max_wall": 10}])")),
            0)
      << err_.str();
  const std::vector<std::string> rows = Rows();
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[1].substr(0, 13), "0,,,,success,");  // three override columns, all empty
  EXPECT_NE(rows[2].find(",refused,"), std::string::npos) << rows[2];
  EXPECT_NE(rows[2].find("x0"), std::string::npos) << rows[2];
  EXPECT_NE(rows[3].find(",max-steps,"), std::string::npos) << rows[3];
  EXPECT_NE(rows[4].find(",refused,method.max_wall: not available per member"), std::string::npos)
      << rows[4];
  EXPECT_NE(out_.str().find("1 succeeded, 3 failed or refused"), std::string::npos) << out_.str();
}

TEST_F(SweepRun, ABadBaseSceneOrAnExistingFolderWritesNothing) {
  EXPECT_EQ(Run(R"({"scene": {"problem": {"type": "dvi", "f": ["-x1"]}, "horizon": 1}})"), 2);
  EXPECT_NE(err_.str().find("sweep.scene: "), std::string::npos) << err_.str();
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  fs::create_directories(dir_ / "out");
  EXPECT_EQ(Run(SweepText("")), 2);
  EXPECT_NE(err_.str().find("exists; the sweep writes a new folder"), std::string::npos)
      << err_.str();
  EXPECT_TRUE(fs::is_empty(dir_ / "out"));
}

}  // namespace
}  // namespace dvi::dvisim
