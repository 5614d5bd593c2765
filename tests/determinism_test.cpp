// SPDX-License-Identifier: Apache-2.0
// Reruns give identical answers: every run listed in determinism_runs.txt
// is repeated in separate processes, one with address-space randomization
// off (setarch -R) and the others with it on, and their outputs must agree
// byte for byte. Arithmetic that depends on memory addresses (an order taken
// from pointers or address-seeded hashes, uninitialized memory, alignment-
// dependent vectorization) shows as a difference here.
#include <glob.h>
#include <sys/utsname.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/dvisim_fixture.hpp"

namespace dvi {
namespace {

using testing::RunOutcome;

// Runs with randomization on, each compared with the one without. A source
// of address dependence need not show in every pair (GiNaC's term order gave
// the half-bridge box-dvi scene 5 different outputs in 10 runs, the dvi one
// 3), so two such runs square the chance that one slips through (a pair that
// shows it half the time misses it a quarter of the time), for half again
// the time of one.
constexpr int kRandomizedRuns = 2;

// One line of the list: `run SCENE [options]` or `command PROGRAM [arguments]`.
struct ListedRun {
  std::string kind;  // "run", "command", or "error" for a line that is neither
  std::string target;  // the scene, or the program, with {source} and {build} expanded
  std::string arguments;
  std::string name;  // for the test's name: letters, digits and _
  // A glob's scene under a forced --method: a scene that does not take the
  // method (a boundary scene under `event`) is refused with exit 2, which is
  // compared like any failure rather than taken for a mistake in the list.
  bool refusal_allowed = false;
};

// The line as gtest shows the parameter, scenes relative to the repository.
void PrintTo(const ListedRun& run, std::ostream* out) {
  const std::string source = std::string(DVI_SOURCE_DIR) + "/";
  const bool inside = run.target.compare(0, source.size(), source) == 0;
  *out << run.kind << " " << (inside ? run.target.substr(source.size()) : run.target) << " "
       << run.arguments;
}

std::string Expand(std::string text) {
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{source}", DVI_SOURCE_DIR},
                                   {"{build}", DVI_BUILD_DIR}})
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at))
      text.replace(at, key.size(), value);
  return text;
}

std::string TestName(const std::string& target, const std::string& arguments) {
  std::string name;
  for (const char c : target.substr(target.find_last_of('/') + 1) + " " + arguments)
    name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

// The runs of the list, scene globs expanded (in the order glob sorts them).
// A malformed line becomes a run of kind "error" that fails naming it.
std::vector<ListedRun> ReadRuns() {
  std::vector<ListedRun> runs;
  std::ifstream list(DVI_DETERMINISM_RUNS);
  std::string line;
  for (int number = 1; std::getline(list, line); ++number) {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    ListedRun run;
    std::string target;
    if (!(words >> run.kind >> target)) continue;
    std::string word, as_written;
    while (words >> word) {
      run.arguments += (run.arguments.empty() ? "" : " ") + Expand(word);
      as_written += " " + word.substr(word.find_last_of('/') + 1);
    }
    if (run.kind == "command") {
      run.target = Expand(target);
      run.name = TestName(run.target, as_written);
      runs.push_back(run);
      continue;
    }
    glob_t matches;
    const std::string pattern = std::string(DVI_SOURCE_DIR) + "/" + Expand(target);
    const bool found = run.kind == "run" && glob(pattern.c_str(), 0, nullptr, &matches) == 0;
    if (!found) {
      run.kind = "error";
      run.target = std::string(DVI_DETERMINISM_RUNS) + ":" + std::to_string(number) + ": \"" +
                   line + "\" is not `run SCENE_GLOB [options]` with a matching scene, nor " +
                   "`command PROGRAM [arguments]`";
      run.name = "line_" + std::to_string(number);
      runs.push_back(run);
      continue;
    }
    run.refusal_allowed =
        target.find_first_of("*?[") != std::string::npos && run.arguments.find("--method") == 0;
    for (std::size_t k = 0; k < matches.gl_pathc; ++k) {
      run.target = matches.gl_pathv[k];
      run.name = TestName(run.target, run.arguments);
      runs.push_back(run);
    }
    globfree(&matches);
  }
  if (runs.empty())
    runs.push_back({"error", std::string(DVI_DETERMINISM_RUNS) + " lists no runs", "", "empty"});
  // Names must be unique; a repeated run gets its position appended.
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (runs[j].name == runs[k].name) runs[k].name += "_" + std::to_string(k);
  return runs;
}

// A JSON document without its timings (every field named *seconds).
nlohmann::json WithoutTimings(nlohmann::json value) {
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end();) {
      const std::string& key = it.key();
      if (key.size() >= 7 && key.compare(key.size() - 7, 7, "seconds") == 0) {
        it = value.erase(it);
      } else {
        it.value() = WithoutTimings(it.value());
        ++it;
      }
    }
  } else if (value.is_array()) {
    for (nlohmann::json& element : value) element = WithoutTimings(element);
  }
  return value;
}

// The first line where two texts differ, both versions, or "" when equal.
std::string FirstDifference(const std::string& a, const std::string& b) {
  if (a == b) return "";
  std::istringstream left(a), right(b);
  std::string line_a, line_b;
  for (int line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(left, line_a));
    const bool more_b = static_cast<bool>(std::getline(right, line_b));
    if (!more_a && !more_b) return "they differ in their last byte";
    if (line_a != line_b || more_a != more_b)
      return "line " + std::to_string(line) + ":\n  without randomization: " +
             (more_a ? line_a : "(ended)") + "\n  with randomization:    " +
             (more_b ? line_b : "(ended)");
  }
}

// What a run leaves to compare: the exit code, and then the outputs (for a
// scene that succeeded) or the messages (for one that failed, or a command).
struct Outputs {
  int exit_code = -1;
  std::string texts;  // labelled, one section per file or stream
};

class Determinism : public testing::DvisimBinaryTest,
                    public ::testing::WithParamInterface<ListedRun> {
 protected:
  // Runs `run` in directory `label`, `prefix` (setarch) before it.
  Outputs Execute(const ListedRun& run, const std::string& prefix, const std::string& label) {
    Outputs outputs;
    if (run.kind == "command") {
      const RunOutcome outcome =
          Shell("cd '" + Path("") + "' && " + prefix + "'" + run.target + "' " + run.arguments);
      outputs.exit_code = outcome.exit_code;
      const nlohmann::json document =
          nlohmann::json::parse(outcome.out, nullptr, /*allow_exceptions=*/false);
      outputs.texts = "stdout:\n" +
                      (document.is_discarded() ? outcome.out
                                               : WithoutTimings(document).dump(1) + "\n") +
                      "stderr:\n" + outcome.err;
      return outputs;
    }
    const std::string out = Path(label);
    const RunOutcome outcome = Shell(prefix + "'" + DVISIM_EXECUTABLE + "' run '" + run.target +
                                     "' " + run.arguments + " --out '" + out + "'");
    outputs.exit_code = outcome.exit_code;
    if (outcome.exit_code != 0) {
      outputs.texts = "stderr:\n" + outcome.err;
      return outputs;
    }
    const nlohmann::json summary = nlohmann::json::parse(Slurp(out + "/summary.json"), nullptr,
                                                         /*allow_exceptions=*/false);
    outputs.texts = "trajectory.csv:\n" + Slurp(out + "/trajectory.csv") +
                    "summary.json (timings aside):\n" + WithoutTimings(summary).dump(1) + "\n";
    return outputs;
  }
};

TEST_P(Determinism, RunsAgreeByteForByteWithAndWithoutAddressRandomization) {
  const ListedRun& run = GetParam();
  ASSERT_NE(run.kind, "error") << run.target;
  // With randomization off machine-wide every run has the same addresses and
  // nothing could differ: say so instead of passing.
  const std::string randomization = Slurp("/proc/sys/kernel/randomize_va_space");
  if (randomization.empty() || randomization[0] == '0')
    GTEST_SKIP() << "address-space randomization is off on this machine "
                    "(/proc/sys/kernel/randomize_va_space), so reruns cannot differ by address";
  utsname machine{};
  ASSERT_EQ(uname(&machine), 0);
  const std::string setarch = std::string("setarch ") + machine.machine + " -R ";
  const RunOutcome check = Shell(setarch + "true");
  ASSERT_EQ(check.exit_code, 0) << "`" << setarch << "true` failed (setarch from util-linux is "
                                << "needed, and the personality system call): " << check.err;

  const Outputs fixed = Execute(run, setarch, "without_randomization");
  if (!run.refusal_allowed) {
    EXPECT_NE(fixed.exit_code, 2) << "bad input: " << fixed.texts;
  }
  for (int k = 0; k < kRandomizedRuns; ++k) {
    const Outputs randomized = Execute(run, "", "with_randomization_" + std::to_string(k));
    EXPECT_EQ(randomized.exit_code, fixed.exit_code) << "run " << k << "\n" << randomized.texts;
    const std::string difference = FirstDifference(fixed.texts, randomized.texts);
    EXPECT_EQ(difference, "") << run.kind << " " << run.target << " " << run.arguments
                              << ": run " << k << " with address randomization differs at "
                              << difference;
  }
}

INSTANTIATE_TEST_SUITE_P(Listed, Determinism, ::testing::ValuesIn(ReadRuns()),
                         [](const ::testing::TestParamInfo<ListedRun>& info) { return info.param.name; });

}  // namespace
}  // namespace dvi
