// SPDX-License-Identifier: Apache-2.0
// The instances of Siconos 4.4.0's numerics test suite, read with
// support/siconos_data and solved through dvi::Solve.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/solve.hpp"
#include "support/siconos_data.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The default solve tolerance; every instance must be solved to it.
constexpr double kResidualTolerance = 1e-10;
// Stored solutions are printed with %f (six decimals): rounding leaves at most
// 5e-7, and the recomputed w adds round-off of the same order.
constexpr double kStoredPrintTolerance = 1e-6;

const std::string kInfeasibleLcp = "lcp_Pang_isolated_sol_perturbed";

std::string TestName(const testing::TestParamInfo<std::string>& info) {
  std::string name = test::SiconosInstanceName(info.param);
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

std::vector<std::string> DenseLcpFiles() {
  std::vector<std::string> files;
  for (const std::string& file : test::SiconosDataFiles("lcp"))
    if (file.find("_block") == std::string::npos) files.push_back(file);
  return files;
}

std::vector<std::string> FeasibleLcpFiles() {
  std::vector<std::string> files;
  for (const std::string& file : DenseLcpFiles())
    if (test::SiconosInstanceName(file) != kInfeasibleLcp) files.push_back(file);
  return files;
}

TEST(SiconosData, DirectoriesHoldTheWholeSuite) {
  EXPECT_EQ(DenseLcpFiles().size(), 17u);
  EXPECT_EQ(test::SiconosDataFiles("lcp").size(), 20u);
  EXPECT_EQ(test::SiconosDataFiles("mlcp").size(), 18u);
  EXPECT_EQ(test::SiconosDataFiles("relay").size(), 7u);
}

class SiconosFeasibleLcp : public testing::TestWithParam<std::string> {};

TEST_P(SiconosFeasibleLcp, AutoSolvesToTolerance) {
  const test::SiconosLcpInstance instance = test::ReadSiconosLcp(GetParam());
  const SolveResult result = Solve(instance.lcp);
  RecordProperty("method", std::string(ToString(result.method)));
  RecordProperty("residual", std::to_string(result.residual));
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.method << ": " << result.message;
  EXPECT_LE(result.residual, kResidualTolerance);
  // The residual reported is the one of the z returned.
  const Eigen::VectorXd w = instance.lcp.M * result.z + instance.lcp.q;
  EXPECT_LE(result.z.cwiseMin(w).cwiseAbs().maxCoeff(), kResidualTolerance);
  EXPECT_TRUE(result.has_index_sets);
}

INSTANTIATE_TEST_SUITE_P(Siconos, SiconosFeasibleLcp, testing::ValuesIn(FeasibleLcpFiles()),
                         TestName);

TEST(SiconosLcp, PerturbedPangIsReportedInfeasibleWithCertificate) {
  const test::SiconosLcpInstance instance =
      test::ReadSiconosLcp(test::SiconosDataDirectory() + "/lcp/" + kInfeasibleLcp + ".dat");
  const SolveResult result = Solve(instance.lcp);
  ASSERT_EQ(result.status, SolveStatus::kInfeasible) << result.message;
  const Eigen::VectorXd& y = result.certificate;
  ASSERT_EQ(y.size(), 3);
  // Farkas: y ≥ 0, Mᵀy ≤ 0 and qᵀy < 0 ⇒ {z ≥ 0 : Mz + q ≥ 0} = ∅. The data
  // are small integers and 1e-4, so round-off is the only slack.
  constexpr double kRoundOff = 1e-12;
  EXPECT_GE(y.minCoeff(), 0.0);
  EXPECT_LE((instance.lcp.M.transpose() * y).maxCoeff(), kRoundOff);
  EXPECT_LT(instance.lcp.q.dot(y), -kRoundOff);
}

// An MLCP or relay problem solved through the MCP path: by Newton, to
// kResidualTolerance.
void ExpectSolvedByNewton(const SolveResult& result) {
  EXPECT_EQ(result.method, SolverMethod::kNewton);
  ::testing::Test::RecordProperty("residual", std::to_string(result.residual));
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kResidualTolerance);
}

class SiconosMlcp : public testing::TestWithParam<std::string> {};

TEST_P(SiconosMlcp, SolvedThroughTheMcpPath) {
  const test::SiconosMcpInstance instance = test::ReadSiconosMlcp(GetParam());
  const SolveResult result = Solve(instance.mcp);
  ASSERT_NO_FATAL_FAILURE(ExpectSolvedByNewton(result));
  // Equality rows hold, complementary ones are complementary.
  const Eigen::VectorXd w = instance.M * result.z + instance.q;
  const int n = instance.num_equalities;
  EXPECT_LE(w.head(n).cwiseAbs().maxCoeff(), kResidualTolerance);
  EXPECT_LE(result.z.tail(w.size() - n).cwiseMin(w.tail(w.size() - n)).cwiseAbs().maxCoeff(),
            kResidualTolerance);
}

INSTANTIATE_TEST_SUITE_P(Siconos, SiconosMlcp, testing::ValuesIn(test::SiconosDataFiles("mlcp")),
                         TestName);

class SiconosRelay : public testing::TestWithParam<std::string> {};

TEST_P(SiconosRelay, SolvedThroughTheMcpPath) {
  const test::SiconosMcpInstance instance = test::ReadSiconosRelay(GetParam());
  const SolveResult result = Solve(instance.mcp);
  ASSERT_NO_FATAL_FAILURE(ExpectSolvedByNewton(result));
  EXPECT_TRUE(result.has_index_sets);
}

INSTANTIATE_TEST_SUITE_P(Siconos, SiconosRelay, testing::ValuesIn(test::SiconosDataFiles("relay")),
                         TestName);

// Files whose appended solution is a solution of the problem they hold (the
// others: Buck2 and diodeBridge20 append values of 1e19 and more, PD appends
// diodeBridge's, the deltasigma pair appends a different one of several).
TEST(SiconosMlcp, StoredSolutionsAgreeWithOurs) {
  struct Stored {
    std::string name;
    double w_tolerance;
  };
  const std::vector<Stored> files = {
      {"BuckConverter_mlcp", kStoredPrintTolerance}, {"deudeu_mlcp", kStoredPrintTolerance},
      {"diodeBridge_mlcp", kStoredPrintTolerance},   {"m3n2_mlcp", kStoredPrintTolerance},
      {"relay2_mlcp", kStoredPrintTolerance},        {"relay3_mlcp", kStoredPrintTolerance},
      // The file prints B's entry 4/3 as 1.3333, the stored w uses 4/3:
      // w differs by 3 × (4/3 − 1.3333) = 1e-4.
      {"m2n1_mlcp", 1.01e-4}};
  for (const Stored& stored : files) {
    const test::SiconosMcpInstance instance =
        test::ReadSiconosMlcp(test::SiconosDataDirectory() + "/mlcp/" + stored.name + ".dat");
    ASSERT_GT(instance.stored_z_tail.size(), 0) << stored.name;
    const SolveResult result = Solve(instance.mcp);
    ASSERT_TRUE(result.solved()) << stored.name << ": " << result.message;
    const Eigen::Index size = result.z.size();
    const Eigen::Index m = instance.stored_w_complementary.size();
    EXPECT_LE((result.z.tail(size - 1) - instance.stored_z_tail).cwiseAbs().maxCoeff(),
              kStoredPrintTolerance)
        << stored.name;
    EXPECT_LE((result.w.tail(m) - instance.stored_w_complementary).cwiseAbs().maxCoeff(),
              stored.w_tolerance)
        << stored.name;
  }
}

TEST(SiconosReader, LcpMatrixIsColumnMajor) {
  // lcp_CPS_2 is Example 4.4.7 of [Cottle–Pang–Stone 1992].
  const auto instance =
      test::ReadSiconosLcp(test::SiconosDataDirectory() + "/lcp/lcp_CPS_2.dat");
  EXPECT_EQ(instance.name, "lcp_CPS_2");
  Eigen::Matrix3d M;
  M << 0, -1, 2, 2, 0, -2, -1, 1, 0;
  EXPECT_EQ(instance.lcp.M, M);
  EXPECT_EQ(instance.lcp.q, Eigen::Vector3d(-3, 6, -1));
}

TEST(SiconosReader, MlcpReadsBlocksAndBounds) {
  const auto instance = test::ReadSiconosMlcp(test::SiconosDataDirectory() + "/mlcp/RCD_mlcp.dat");
  EXPECT_EQ(instance.name, "RCD_mlcp");
  EXPECT_EQ(instance.num_equalities, 2);
  Eigen::Matrix3d M;
  M << 0.1, -0.1, -1, -1.505, 0.5, 0, 0, -1, 0;
  EXPECT_EQ(instance.M, M);
  EXPECT_EQ(instance.q, Eigen::Vector3d(0, 0.495, 0));
  EXPECT_EQ(instance.mcp.lower, Eigen::Vector3d(-kInf, -kInf, 0));
  EXPECT_EQ(instance.mcp.upper, Eigen::Vector3d::Constant(kInf));
  EXPECT_EQ(instance.stored_z_tail.size(), 0);
}

TEST(SiconosReader, MlcpWithNonSquareMIsReadFromAbcd) {
  const auto instance =
      test::ReadSiconosMlcp(test::SiconosDataDirectory() + "/mlcp/Rectangular_mlcp.dat");
  EXPECT_EQ(instance.M, (Eigen::Matrix2d() << 1, -1, 1, 1).finished());
  EXPECT_EQ(instance.q, Eigen::Vector2d(0, -1));
  EXPECT_EQ(instance.num_equalities, 1);
}

TEST(SiconosReader, MlcpStoredSolutionIsSplit) {
  const auto instance = test::ReadSiconosMlcp(test::SiconosDataDirectory() + "/mlcp/m2n1_mlcp.dat");
  EXPECT_EQ(instance.stored_z_tail, Eigen::Vector2d(0, 3));
  EXPECT_EQ(instance.stored_w_complementary, Eigen::Vector2d(5, 0));
}

TEST(SiconosReader, RelayReadsBounds) {
  const auto instance = test::ReadSiconosRelay(test::SiconosDataDirectory() + "/relay/relay_2x2.dat");
  EXPECT_EQ(instance.M, Eigen::Matrix2d::Identity());
  EXPECT_EQ(instance.q, Eigen::Vector2d(-0.5, 0.5));
  EXPECT_EQ(instance.mcp.lower, Eigen::Vector2d(-1, -1));
  EXPECT_EQ(instance.mcp.upper, Eigen::Vector2d(1, 1));
}

class SiconosReaderErrors : public testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("dvi_siconos_reader_" + name);
    std::ofstream(path) << text;
    paths_.push_back(path);
    return path.string();
  }
  void TearDown() override {
    for (const auto& path : paths_) std::filesystem::remove(path);
  }

  template <typename Read>
  void ExpectError(Read read, const std::string& path, const std::string& part) {
    try {
      read(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    }
  }

 private:
  std::vector<std::filesystem::path> paths_;
};

TEST_F(SiconosReaderErrors, NameFileAndLine) {
  const auto lcp = [](const std::string& p) { test::ReadSiconosLcp(p); };
  const auto mlcp = [](const std::string& p) { test::ReadSiconosMlcp(p); };
  const auto relay = [](const std::string& p) { test::ReadSiconosRelay(p); };
  const std::string truncated = Write("truncated.dat", "2\n0\n2\n2\n2 2\n1 0\n0 1\n-1\n");
  ExpectError(lcp, truncated, truncated + ":8: unexpected end of file while reading q[1]");
  const std::string word = Write("word.dat", "2\n0\n2\n2\n2 2\n1 0\nx 1\n-1 -1\n");
  ExpectError(lcp, word, word + ":7: expected a number for M(0,1), got 'x'");
  const std::string block =
      test::SiconosDataDirectory() + "/lcp/lcp_deudeu_block.dat";
  ExpectError(lcp, block, block + ":2: M has storage type 1");
  const std::string wrong_size = Write("size.dat", "3\n0\n2\n2\n2 2\n1 0 0 1\n-1 -1\n");
  ExpectError(lcp, wrong_size, wrong_size + ":6: M is 2x2, expected 3x3");
  const std::string disagree = Write(
      "disagree.dat", "1\n1\n1\n1\n0 1 2\n0 1\n0\n2\n2\n2 2\n1 0\n-1 1\n-1 1\n1\n1\n-1\n2\n-1\n1\n");
  ExpectError(mlcp, disagree, disagree + ":19: M(1,0) = 0.000000 disagrees");
  const std::string blocks = Write("blocks.dat", "1\n0\n1\n1\n0 3\n");
  ExpectError(mlcp, blocks, blocks + ":5: blocksRows must increase up to n + m = 2");
  const std::string bounds =
      Write("bounds.dat", "1\n0\n1\n1\n1 1\n1\n0\n1\n-1\n");
  ExpectError(relay, bounds, bounds + ":9: lb[0] > ub[0]");
  ExpectError(lcp, "/nonexistent/x.dat", "/nonexistent/x.dat: cannot open the file");
}

}  // namespace
}  // namespace dvi
