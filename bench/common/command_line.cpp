// SPDX-License-Identifier: Apache-2.0
#include "command_line.hpp"

#include <exception>
#include <iostream>
#include <stdexcept>

namespace dvi::bench {

CommandLine& CommandLine::Value(std::string flag, std::function<void(const std::string&)> read) {
  options_.push_back({std::move(flag), std::move(read), {}});
  return *this;
}

CommandLine& CommandLine::Switch(std::string flag, std::function<void()> set) {
  options_.push_back({std::move(flag), {}, std::move(set)});
  return *this;
}

void CommandLine::Parse(int argc, char** argv) const {
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    const Option* option = nullptr;
    for (const Option& candidate : options_)
      if (candidate.flag == argument) option = &candidate;
    if (!option) throw std::invalid_argument("unknown argument " + argument);
    if (!option->read) {
      option->set();
      continue;
    }
    if (i + 1 >= argc) throw std::invalid_argument(argument + " needs a value");
    option->read(argv[++i]);
  }
}

int BenchMain(const std::string& name, const std::string& usage, const std::function<int()>& run) {
  try {
    return run();
  } catch (const std::exception& error) {
    std::cerr << name << ": " << error.what() << "\nusage: " << usage << "\n";
    return 2;
  }
}

}  // namespace dvi::bench
