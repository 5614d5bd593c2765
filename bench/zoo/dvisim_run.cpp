// SPDX-License-Identifier: Apache-2.0
#include "dvisim_run.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.hpp"

namespace dvi::zoo {
namespace {

using Json = nlohmann::json;

std::string FirstLine(const std::string& path, const std::string& scene) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  // dvisim prefixes "dvisim: SCENE: ".
  const std::string prefix = "dvisim: " + scene + ": ";
  if (line.rfind(prefix, 0) == 0) line = line.substr(prefix.size());
  return line;
}

// Rows of trajectory.csv: t and the first n state columns.
std::vector<std::pair<double, Eigen::VectorXd>> ReadRows(const std::string& path, int n) {
  std::vector<std::pair<double, Eigen::VectorXd>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string cell;
    std::getline(fields, cell, ',');
    const double t = std::stod(cell);
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) {
      std::getline(fields, cell, ',');
      x(i) = std::stod(cell);
    }
    rows.emplace_back(t, x);
  }
  return rows;
}

}  // namespace

DvisimRun RunDvisim(const ZooModel& model, const PiecewiseLinearReference& reference,
              const ReferenceError& error, const std::string& method, const std::string& dvisim,
              const std::string& scene, const std::filesystem::path& out, double timeout) {
  namespace fs = std::filesystem;
  DvisimRun run;
  run.method = method;
  const fs::path dir = out / "runs" / model.key / method;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  const std::string stderr_path = (out / "runs" / model.key / (method + ".stderr")).string();
  const ChildExit process =
      RunChild({dvisim, "run", scene, "--method", method, "--out", dir.string()}, stderr_path,
               timeout);
  run.exit_code = process.exit_code;
  run.timed_out = process.timed_out;
  if (process.timed_out) {
    run.status = "timeout";
    run.message = "killed after " + std::to_string(static_cast<int>(timeout)) + " s";
    return run;
  }
  if (process.exit_code != 0) {
    run.status = "exit " + std::to_string(process.exit_code);
    run.message = FirstLine(stderr_path, scene);
    return run;
  }
  std::ifstream summary_file(dir / "summary.json");
  const Json summary = Json::parse(summary_file);
  run.status = summary.at("status").get<std::string>();
  run.seconds = summary.at("stats").at("wall_seconds").get<double>();
  std::set<double> times;
  for (const Json& event : summary.at("events")) times.insert(event.at("time").get<double>());
  run.switches = static_cast<int>(times.size());
  std::map<std::string, int> counts;
  double event_time = 0;
  const std::regex t_star(R"(accumulation predicted at t\* = ([0-9.eE+-]+))");
  for (const Json& interval : summary.at("method")) {
    const std::string name = interval.at("name").get<std::string>();
    ++counts[name];
    // The issue's goal counts a Zeno extrapolation as event-driven.
    if (name == "event" || name == "zeno-extrapolation") {
      event_time += interval.at("to").get<double>() - interval.at("from").get<double>();
    }
    std::smatch match;
    const std::string reason = interval.at("reason").get<std::string>();
    if (name == "zeno-extrapolation") {  // ends at t*, to the double
      run.predicted_t_star = interval.at("to").get<double>();
      run.t_star_resolution = 0;
    } else if (std::isnan(run.predicted_t_star) && std::regex_search(reason, match, t_star)) {
      const std::string printed = match[1];
      run.predicted_t_star = std::stod(printed);
      const std::size_t point = printed.find('.');
      const int decimals =
          point == std::string::npos ? 0 : static_cast<int>(printed.size() - point - 1);
      run.t_star_resolution = 0.5 * std::pow(10.0, -decimals);
    }
  }
  run.event_fraction = event_time / model.horizon;
  for (const auto& [name, count] : counts) {
    run.intervals += (run.intervals.empty() ? "" : ", ") + std::to_string(count) + " " + name;
  }
  run.error = 0;
  run.zeno_error = std::isnan(model.zeno_time) ? NAN : 0;
  for (const auto& [t, x] : ReadRows((dir / "trajectory.csv").string(), model.n())) {
    if (t <= 0) continue;  // x(0⁻): the rectifiers jump at t = 0
    run.error = std::max(run.error, error.At(t, x));
    if (t >= model.zeno_time) {
      run.zeno_error =
          std::max(run.zeno_error, (x - reference.X(t)).lpNorm<Eigen::Infinity>());
    }
  }
  if (fs::exists(dir / "plot.png")) run.plot = (dir / "plot.png").string();
  return run;
}

}  // namespace dvi::zoo
