// SPDX-License-Identifier: Apache-2.0
#include "study_command.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "dvi/error.hpp"
#include "plot.hpp"
#include "solve_command.hpp"
#include "study.hpp"
#include "study_report.hpp"

namespace dvi::dvisim {
namespace {

namespace fs = std::filesystem;

constexpr int kBarWidth = 40;

void Write(const fs::path& path, const std::string& contents) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream << contents;
  stream.close();
  if (!stream) throw std::runtime_error("cannot write " + path.string());
}

std::string ReadBack(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::ostringstream contents;
  contents << stream.rdbuf();
  return contents.str();
}

}  // namespace

void WriteStudyFolder(const StudyResult& result, int jobs, const fs::path& temporary,
                      const fs::path& dir) {
  std::error_code error;
  if (!fs::create_directory(temporary, error) || error)
    throw std::runtime_error("cannot create " + temporary.string() + " (" + error.message() + ")");
  Write(temporary / "study.csv", StudyCsv(result));
  Write(temporary / "study.json", StudyJson(result, jobs).dump(2) + "\n");
  Write(temporary / "stability.md", StabilityMarkdown(result));
  try {
    RunGnuplot(temporary.string(), WorkPrecisionScript(result), "study: work_precision chart");
  } catch (const InputError& error) {
    throw std::runtime_error(error.what());  // the tool failed, not the input
  }
  Write(temporary / "index.html", StudyHtml(result, ReadBack(temporary / "work_precision.svg")));
  fs::rename(temporary, dir, error);
  if (error)
    throw std::runtime_error("cannot move " + temporary.string() + " to " + dir.string() + " (" +
                             error.message() + ")");
}

namespace {

void PrintSummary(const StudyResult& result, const fs::path& dir, std::ostream& out) {
  const ReferenceReport& reference = result.reference;
  out << result.title << ": " << result.runs.size() << " runs against the " << reference.kind
      << " reference (" << reference.description << ")\n";
  if (!reference.cross_check.empty())
    out << "  cross-check: " << reference.cross_check << ": agreement "
        << StudyNumber(reference.agreement) << ", bound " << StudyNumber(reference.bound)
        << (reference.agree ? " (agree)" : " (DISAGREE)") << "\n";
  for (const Slope& slope : result.slopes)
    if (slope.rungs >= 3)
      out << "  " << ToString(slope.method) << ": order " << StudyNumber(slope.slope) << " over "
          << StudyNumber(slope.decades) << " decades\n";
  out << "  wrote " << (dir / "index.html").string() << " (and study.csv, study.json, "
      << "stability.md, work_precision.png, work_precision.svg)\n";
}

}  // namespace

int RunStudyCommand(const StudyCommand& command, std::ostream& out, std::ostream& err) {
  try {
    if (command.out_dir.empty()) throw InputError("--out: expected a directory");
    fs::path dir(command.out_dir);
    if (dir.filename().empty()) dir = dir.parent_path();
    std::error_code ignored;
    if (fs::exists(fs::symlink_status(dir, ignored)))
      throw InputError("--out: " + dir.string() +
                       " exists; the study writes a new folder (remove it or name another)");
    if (command.jobs < 0) throw InputError("--jobs: expected a number of runs at once ≥ 1");
    if (command.repeats < 1) throw InputError("--repeats: expected a number of timing samples ≥ 1");
    const Scene scene = ReadScene(command.scene_path);
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ignored))
      throw InputError("--out: the folder " + parent.string() + " of " + dir.string() +
                       " does not exist");
    StudyOptions options;
    options.jobs = command.jobs > 0
                       ? command.jobs
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    options.repeats = command.repeats;
    if (command.progress_bar)
      options.progress = [&err](int done, int total) {
        const int filled = kBarWidth * done / total;
        err << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(kBarWidth - filled), ' ') << "] " << done << "/"
            << total << " runs" << std::flush;
      };
    StudyResult result;
    try {
      result = RunStudy(scene, options);
    } catch (const InputError& error) {
      throw InputError(command.scene_path + ": " + error.what());
    }
    if (command.progress_bar) err << "\n";
    const fs::path temporary =
        parent / ("." + dir.filename().string() + ".tmp-" + std::to_string(::getpid()));
    try {
      WriteStudyFolder(result, options.jobs, temporary, dir);
    } catch (...) {
      fs::remove_all(temporary, ignored);
      throw;
    }
    PrintSummary(result, dir, out);
    return kExitSolved;
  } catch (const InputError& error) {
    err << "dvisim: " << error.what() << " (no files written)\n";
    return kExitBadInput;
  } catch (const InvalidInputError& error) {
    err << "dvisim: " << command.scene_path << ": " << error.what() << " (no files written)\n";
    return kExitBadInput;
  } catch (const std::exception& error) {
    err << "dvisim: " << command.scene_path << ": the study failed: " << error.what()
        << " (no files written)\n";
    return kExitNumericalFailure;
  }
}

}  // namespace dvi::dvisim
