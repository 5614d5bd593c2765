// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace dvi::testing {

/// What a run of the built dvisim produced.
struct RunOutcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// A test that runs the built dvisim (DVISIM_EXECUTABLE, a compile
/// definition of the test target) in a fresh directory of its own, removed
/// afterwards.
class DvisimBinaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    directory_ = std::filesystem::temp_directory_path() /
                 (std::string("dvisim_") + test->test_suite_name() + "_" +
                  std::to_string(::getpid()) + "_" + test->name());
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  /// A path in the test's directory.
  std::string Path(const std::string& name) const { return (directory_ / name).string(); }

  /// Writes a file in the test's directory; returns its path.
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name)) << text;
    return Path(name);
  }

  /// Runs `dvisim ARGUMENTS`, capturing exit code, stdout and stderr.
  RunOutcome Dvisim(const std::string& arguments) const {
    return Shell(std::string("'") + DVISIM_EXECUTABLE + "' " + arguments);
  }

  /// Runs a shell command line, capturing exit code, stdout and stderr.
  RunOutcome Shell(const std::string& command_line) const {
    const std::string out = Path("stdout.txt");
    const std::string err = Path("stderr.txt");
    const std::string command = command_line + " >'" + out + "' 2>'" + err + "'";
    const int status = std::system(command.c_str());
    RunOutcome run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = Slurp(out);
    run.err = Slurp(err);
    return run;
  }

  /// The whole text of a file ("" when it cannot be read).
  static std::string Slurp(const std::string& path) {
    std::ifstream stream(path);
    std::ostringstream text;
    text << stream.rdbuf();
    return text.str();
  }

 private:
  std::filesystem::path directory_;
};

}  // namespace dvi::testing
