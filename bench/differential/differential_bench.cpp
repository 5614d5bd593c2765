// SPDX-License-Identifier: Apache-2.0
// Differential testing of the event-driven core at scale (issue 27): random
// problems of each class (tests/support/random_dvis.hpp) over a seed range,
// every method against the Richardson-extrapolated time-stepping reference
// (tests/support/differential_check.hpp). Writes a markdown summary: per
// class the instances, agreements, refusals, disagreements and instances
// without a reference, then each disagreement with its one-line reproducer.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "support/differential_check.hpp"
#include "support/random_dvis.hpp"
#include "timing.hpp"

namespace {

using dvi::testing::DifferentialResult;
using dvi::testing::Verdict;

struct Settings {
  std::vector<std::string> classes;
  unsigned first_seed = 1;
  unsigned seeds = 100;
  double rtol = 1e-10;
  double atol = 1e-12;
  std::string out;
  bool verbose = false;
  unsigned jobs = 1;
};

struct Tally {
  long instances = 0, no_reference = 0;
  // Switches of the reference per instance with a reference.
  long switches = 0, several_switches = 0;
  std::map<std::string, std::map<Verdict, long>> by_method;
  double seconds = 0;
};

std::string Line(const std::string& text) {
  std::string line = text;
  for (char& c : line)
    if (c == '\n' || c == '|') c = ' ';
  return line;
}

void Print(const DifferentialResult& result, std::ostream& out) {
  out << result.problem_class << " seed " << result.seed << " (" << result.structure << "): ";
  if (!result.reference.available) out << "no reference: " << result.reference.why_not << "; ";
  for (const auto& method : result.methods) {
    out << method.method << " " << ToString(method.verdict);
    if (method.verdict != Verdict::kNoReference) {
      char ratio[32];
      std::snprintf(ratio, sizeof ratio, " %.2g", method.worst_ratio);
      out << ratio;
    }
    out << " (" << method.steps << " steps, " << method.events << " events)";
    if (!method.detail.empty()) out << " [" << method.detail << "]";
    out << "; ";
  }
  out << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  CLI::App app("Differential testing of the event-driven integrators against Richardson-"
               "extrapolated time-stepping on random problems of known structure");
  app.add_option("--class", settings.classes, "problem classes (default: all)");
  app.add_option("--first-seed", settings.first_seed, "first seed of the range");
  app.add_option("--seeds", settings.seeds, "seeds per class")->check(CLI::Range(1u, 1000000u));
  app.add_option("--seed", [&settings](const CLI::results_t& values) {
       settings.first_seed = static_cast<unsigned>(std::stoul(values[0]));
       settings.seeds = 1;
       return true;
     }, "one seed (a reproducer)");
  app.add_option("--rtol", settings.rtol, "rtol of the event-driven and IDA runs")
      ->check(CLI::PositiveNumber);
  app.add_option("--atol", settings.atol, "atol of the event-driven and IDA runs")
      ->check(CLI::PositiveNumber);
  app.add_option("--out", settings.out, "write the markdown summary here (default: stdout)");
  app.add_flag("--verbose", settings.verbose, "one line per instance on stderr");
  app.add_option("--jobs", settings.jobs, "instances run at once (threads)")
      ->check(CLI::Range(1u, 64u));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  if (settings.classes.empty())
    for (const auto& problem_class : dvi::testing::RandomDviClasses())
      settings.classes.emplace_back(problem_class.name);

  dvi::testing::DifferentialOptions options;
  options.rtol = settings.rtol;
  options.atol = settings.atol;
  // Every instance, run by `jobs` threads in any order (each instance owns
  // its problem, integrators and reference), then tallied in order so that
  // the summary does not depend on the schedule.
  struct Instance {
    std::string problem_class;
    unsigned seed = 0;
    DifferentialResult result;
    std::string error;  // what it threw, if it did
    double seconds = 0;
  };
  std::vector<Instance> instances;
  for (const std::string& problem_class : settings.classes)
    for (unsigned k = 0; k < settings.seeds; ++k)
      instances.push_back({problem_class, settings.first_seed + k, {}, {}, 0});
  std::atomic<std::size_t> next{0};
  std::mutex print;
  const auto work = [&] {
    for (std::size_t i = next++; i < instances.size(); i = next++) {
      Instance& instance = instances[i];
      const auto start = std::chrono::steady_clock::now();
      try {
        instance.result = dvi::testing::RunDifferential(
            dvi::testing::GenerateRandomDvi(instance.problem_class, instance.seed), options);
      } catch (const std::exception& error) {
        instance.error = error.what();
      }
      instance.seconds = dvi::bench::SecondsSince(start);
      if (settings.verbose && instance.error.empty()) {
        const std::lock_guard<std::mutex> lock(print);
        Print(instance.result, std::cerr);
      }
    }
  };
  std::vector<std::thread> threads;
  for (unsigned j = 1; j < settings.jobs; ++j) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();

  std::map<std::string, Tally> tallies;
  std::vector<std::string> disagreements;
  for (const Instance& instance : instances) {
    Tally& tally = tallies[instance.problem_class];
    ++tally.instances;
    if (!instance.error.empty()) {
      // A valid problem must not make anything throw: listed with the
      // disagreements.
      disagreements.push_back("| `differential_bench --class " + instance.problem_class +
                              " --seed " + std::to_string(instance.seed) + "` | (any) | threw: " +
                              Line(instance.error) + " |");
      continue;
    }
    const DifferentialResult& result = instance.result;
    tally.seconds += instance.seconds;
    if (!result.reference.available) {
      ++tally.no_reference;
    } else {
      const auto count = static_cast<long>(result.reference.switches.size());
      tally.switches += count;
      if (count >= 2) ++tally.several_switches;
    }
    for (const auto& method : result.methods) {
      ++tally.by_method[method.method][method.verdict];
      if (method.verdict == Verdict::kDisagree)
        disagreements.push_back("| `" + result.Reproducer() + "` | " + method.method + " | " +
                                Line(method.detail) + " |");
    }
  }

  std::ostringstream summary;
  summary << "| class | instances | no reference | switches (mean, ≥ 2) | method | agree | refused | "
             "known gap | disagree | no reference | seconds |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& problem_class : settings.classes) {
    const Tally& tally = tallies[problem_class];
    bool first = true;
    for (const auto& [method, verdicts] : tally.by_method) {
      const auto count = [&verdicts = verdicts](Verdict verdict) {
        const auto found = verdicts.find(verdict);
        return found == verdicts.end() ? 0L : found->second;
      };
      std::string switches;
      if (first && tally.instances > tally.no_reference) {
        const long with_reference = tally.instances - tally.no_reference;
        char text[64];
        std::snprintf(text, sizeof text, "%.1f, %.0f %%",
                      static_cast<double>(tally.switches) / with_reference,
                      100.0 * tally.several_switches / with_reference);
        switches = text;
      }
      summary << "| " << (first ? problem_class : "") << " | "
              << (first ? std::to_string(tally.instances) : "") << " | "
              << (first ? std::to_string(tally.no_reference) : "") << " | " << switches << " | "
              << method << " | "
              << count(Verdict::kAgree) << " | " << count(Verdict::kRefused) << " | "
              << count(Verdict::kKnownGap) << " | " << count(Verdict::kDisagree) << " | " << count(Verdict::kNoReference) << " | ";
      if (first) {
        char seconds[32];
        std::snprintf(seconds, sizeof seconds, "%.1f", tally.seconds);
        summary << seconds;
      }
      summary << " |\n";
      first = false;
    }
  }
  summary << "\n" << disagreements.size() << " disagreements";
  if (!disagreements.empty()) {
    summary << ":\n\n| reproducer | method | what |\n|---|---|---|\n";
    for (const std::string& line : disagreements) summary << line << "\n";
  } else {
    summary << ".\n";
  }
  if (settings.out.empty()) {
    std::cout << summary.str();
  } else {
    std::ofstream file(settings.out);
    file << summary.str();
    if (!file) {
      std::cerr << "error: could not write " << settings.out << "\n";
      return 1;
    }
  }
  return disagreements.empty() ? 0 : 2;
}
