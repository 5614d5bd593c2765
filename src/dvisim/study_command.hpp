// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

#include "study.hpp"

namespace dvi::dvisim {

/// `dvisim study SCENE.json --out DIR [--jobs N] [--repeats R] [--progress]`.
struct StudyCommand {
  std::string scene_path;
  std::string out_dir;        ///< Must not exist: the study writes a new folder.
  int jobs = 0;               ///< Runs at once; 0: one per core.
  int repeats = 3;            ///< Timing samples per run.
  bool progress_bar = false;  ///< Draw "[####  ] k/N runs" on `err`.
};

/// Runs the study (study.hpp) and writes DIR/study.csv, study.json,
/// stability.md, work_precision.png, work_precision.svg and index.html:
/// into a temporary folder beside DIR, renamed to DIR at the end, so DIR
/// appears whole or not at all. Returns 0, 1 (no reference could be found,
/// or gnuplot failed: nothing written) or 2 (bad input: the scene, the
/// options, or an existing DIR; nothing written), with a one-line message on
/// `err`. A summary goes to `out`.
int RunStudyCommand(const StudyCommand& command, std::ostream& out, std::ostream& err);

/// Writes the study's files into `temporary` (created here), then renames
/// it to `dir`. @throws std::runtime_error (also when gnuplot fails).
void WriteStudyFolder(const StudyResult& result, int jobs, const std::filesystem::path& temporary,
                      const std::filesystem::path& dir);

}  // namespace dvi::dvisim
