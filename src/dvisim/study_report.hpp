// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "study.hpp"

namespace dvi::dvisim {

/// A number as study.csv and index.html both show it: 6 significant
/// digits, "" for NaN (not measured).
std::string StudyNumber(double value);

/// study.csv, one row per run in StudyResult::runs order. The columns
/// (StudyCsvHeader) end with the timing ones, seconds and repeats, the only
/// ones that differ between two studies of the same scene.
std::string StudyCsvHeader();
std::string StudyCsv(const StudyResult& result);
/// The CSV fields of one run, as in study.csv (text unquoted).
std::vector<std::string> StudyCsvFields(const StudyRun& run);

/// stability.md: the reference, the fitted orders, and the outcome of every
/// run per method and rung (converged / wrong mode sequence / refused /
/// failed), with the reasons as numbered notes.
std::string StabilityMarkdown(const StudyResult& result);

/// study.json: the reference and its cross-check, the orders, the cost at
/// which each method reaches a few errors, and the machine's load.
nlohmann::ordered_json StudyJson(const StudyResult& result, int jobs);

/// The gnuplot script drawing work_precision.png and work_precision.svg
/// (paths relative to the output folder): max error against wall time and
/// against RHS evaluations, one curve per method over its converged runs.
std::string WorkPrecisionScript(const StudyResult& result);

/// index.html: self-contained (the chart inlined as a data: URI, no script
/// file, no network), with the reference, the orders, the cost table, the
/// stability tables and every run as in study.csv (table id "runs").
std::string StudyHtml(const StudyResult& result, const std::string& svg);

}  // namespace dvi::dvisim
