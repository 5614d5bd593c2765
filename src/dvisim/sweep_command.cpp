// SPDX-License-Identifier: Apache-2.0
#include "sweep_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "csv_text.hpp"
#include "dvi/ensemble.hpp"
#include "dvi/error.hpp"
#include "json_reading.hpp"
#include "run_command.hpp"
#include "scene_file.hpp"
#include "scene_limits.hpp"
#include "solve_command.hpp"
#include "study_settings.hpp"
#include "sweep_file.hpp"

namespace dvi::dvisim {
namespace {

namespace fs = std::filesystem;

// One member's scene, checked as `dvisim run` checks a scene file.
Scene MemberSceneChecked(const Sweep& sweep, std::size_t member) {
  Scene scene = ParseScene(MemberScene(sweep, member).dump());
  // WallClockLimit ends the process: one member's budget would end them all.
  if (scene.max_wall > 0)
    throw InputError("method.max_wall: not available per member of a sweep (it would end every "
                     "member's run); remove it from the scene");
  CheckSceneLimits(scene);
  return scene;
}

std::string StatusText(const EnsembleResult& result) {
  return result.refused ? "refused" : std::string(ToString(result.status));
}

std::string SweepCsv(const Sweep& sweep, const std::vector<EnsembleResult>& results) {
  Eigen::Index states = 0;
  for (const EnsembleResult& result : results) states = std::max(states, result.x_final.size());
  std::string csv = "member";
  for (const std::string& column : sweep.columns) csv += "," + CsvField(column);
  csv += ",status,message,t_final";
  for (Eigen::Index i = 1; i <= states; ++i) csv += ",x" + std::to_string(i);
  csv += ",events,steps,rhs_evals,certified,wall_seconds\n";
  for (const EnsembleResult& result : results) {
    csv += std::to_string(result.member);
    const auto& overrides = sweep.members[result.member];
    for (const std::string& column : sweep.columns) {
      // The last override of a pointer wins, as in MemberScene.
      std::string value;
      for (const auto& [pointer, given] : overrides)
        if (pointer == column) value = given.is_string() ? given.get<std::string>() : given.dump();
      csv += "," + CsvField(value);
    }
    csv += "," + StatusText(result) + "," + CsvField(result.message) + "," +
           ExactNumber(result.t_final);
    for (Eigen::Index i = 0; i < states; ++i)
      csv += "," + (i < result.x_final.size() ? ExactNumber(result.x_final[i]) : std::string());
    csv += "," + std::to_string(result.events) + "," + std::to_string(result.stats.steps) + "," +
           std::to_string(result.stats.rhs_evals) + "," + (result.certified ? "true" : "false") +
           "," + ShortNumber(result.stats.wall_seconds) + "\n";
  }
  return csv;
}

void Write(const fs::path& path, const std::string& contents) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream << contents;
  stream.close();
  if (!stream) throw std::runtime_error("cannot write " + path.string());
}

// The whole folder is written beside its place and moved in at once.
void WriteSweepFolder(const Sweep& sweep, const std::vector<EnsembleResult>& results,
                      const fs::path& temporary, const fs::path& dir) {
  std::error_code error;
  if (!fs::create_directory(temporary, error) || error)
    throw std::runtime_error("cannot create " + temporary.string() + " (" + error.message() + ")");
  Write(temporary / "sweep.csv", SweepCsv(sweep, results));
  for (const EnsembleResult& result : results) {
    if (!result.trajectory) continue;
    const Scene scene = MemberSceneChecked(sweep, result.member);
    const fs::path folder = temporary / "members" / std::to_string(result.member);
    fs::create_directories(folder, error);
    if (error) throw std::runtime_error("cannot create " + folder.string());
    Write(folder / "trajectory.csv", TrajectoryCsv(scene, *result.trajectory));
    Write(folder / "summary.json", SummaryJson(scene, *result.trajectory).dump(2) + "\n");
  }
  fs::rename(temporary, dir, error);
  if (error)
    throw std::runtime_error("cannot move " + temporary.string() + " to " + dir.string() + " (" +
                             error.message() + ")");
}

}  // namespace

int RunSweepCommand(const SweepCommand& command, std::ostream& out, std::ostream& err) {
  const bool rank_zero = CurrentEnsembleRank().rank == 0;
  // Only rank 0 speaks and writes. Every rank reads the same files (a
  // shared file system, as MPI sites have) and so reaches the same verdict
  // before the ensemble's collective, which no rank may skip.
  const auto fail = [&](const std::string& text, int code) {
    if (rank_zero) err << "dvisim: " << text << " (no files written)\n";
    return code;
  };
  try {
    Sweep sweep = ParseFile(command.sweep_path, [&](const std::string& text) {
      return ParseSweep(text, command.sweep_path);
    });
    if (command.out_dir) sweep.out_dir = *command.out_dir;
    if (command.trajectories) sweep.trajectories = true;
    fs::path dir(sweep.out_dir);
    if (dir.filename().empty()) dir = dir.parent_path();
    std::error_code ignored;
    if (fs::exists(fs::symlink_status(dir, ignored)))
      throw InputError((command.out_dir ? "--out: " : "sweep.output.dir: ") + dir.string() +
                       " exists; the sweep writes a new folder (remove it or name another)");
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ignored))
      throw InputError("sweep.output.dir: the folder " + parent.string() + " of " + dir.string() +
                       " does not exist");
    // A base scene that is wrong is the sweep's mistake, not a member's.
    try {
      (void)ParseScene(sweep.base.dump());
    } catch (const InputError& error) {
      throw InputError(sweep.base_source + ": " + error.what());
    }

    EnsembleOptions options;
    options.keep_trajectories = sweep.trajectories;
    const std::vector<EnsembleResult> results = RunEnsemble(
        sweep.members.size(),
        [&sweep](std::size_t member) { return IntegrateScene(MemberSceneChecked(sweep, member)); },
        options);
    if (!rank_zero) return kExitSolved;

    const fs::path temporary =
        parent / ("." + dir.filename().string() + ".tmp-" + std::to_string(::getpid()));
    try {
      WriteSweepFolder(sweep, results, temporary, dir);
    } catch (...) {
      fs::remove_all(temporary, ignored);
      throw;
    }
    const auto failed = std::count_if(results.begin(), results.end(),
                                      [](const EnsembleResult& r) { return !r.succeeded(); });
    double wall = 0;
    for (const EnsembleResult& result : results) wall += result.stats.wall_seconds;
    out << "sweep " << command.sweep_path << ": " << results.size() << " members on "
        << CurrentEnsembleRank().size << " rank(s), " << results.size() - static_cast<std::size_t>(failed)
        << " succeeded, " << failed << " failed or refused; " << wall
        << " s of integration\n  wrote " << (dir / "sweep.csv").string()
        << (sweep.trajectories ? " and members/<k>/{trajectory.csv,summary.json}" : "") << "\n";
    return kExitSolved;
  } catch (const InputError& error) {
    return fail(error.what(), kExitBadInput);
  } catch (const InvalidInputError& error) {
    return fail(command.sweep_path + ": " + error.what(), kExitBadInput);
  } catch (const std::exception& error) {
    return fail(command.sweep_path + ": the sweep failed: " + error.what(), kExitNumericalFailure);
  }
}

}  // namespace dvi::dvisim
