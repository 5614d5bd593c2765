// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace dvi::bench {

/// A benchmark's command line: options that take a value (--csv PATH) and
/// switches (--quick), each handed to the caller's function in the order
/// given. Owns: the option table. Source: the flag loops each benchmark
/// wrote before (dae_headline, stepping_vs_siconos, lcp_vs_siconos,
/// work_precision_dae).
class CommandLine {
 public:
  /// `flag VALUE`: read(VALUE).
  CommandLine& Value(std::string flag, std::function<void(const std::string&)> read);
  /// `flag`: set().
  CommandLine& Switch(std::string flag, std::function<void()> set);
  /// @throws std::invalid_argument "unknown argument X" or "X needs a value".
  void Parse(int argc, char** argv) const;

 private:
  struct Option {
    std::string flag;
    std::function<void(const std::string&)> read;  ///< Empty for a switch.
    std::function<void()> set;
  };
  std::vector<Option> options_;
};

/// A benchmark's main(): run()'s exit code; when it throws, "name: what"
/// and "usage: usage" on stderr and exit code 2.
int BenchMain(const std::string& name, const std::string& usage, const std::function<int()>& run);

}  // namespace dvi::bench
