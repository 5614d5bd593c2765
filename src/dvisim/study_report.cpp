// SPDX-License-Identifier: Apache-2.0
#include "study_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "csv_text.hpp"
#include "json_reading.hpp"
#include "work_precision_front.hpp"

namespace dvi::dvisim {
namespace {

// The errors the cost table asks each method for, relative to the
// solution's size: a plot's accuracy, a careful engineer's, and a reference's.
constexpr double kCostTargets[] = {1e-3, 1e-6, 1e-9};

std::string Escape(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '&':
        escaped += "&amp;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

// RFC 4648 base64, for the chart inlined in the page.
std::string Base64(const std::string& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string encoded;
  std::size_t k = 0;
  for (; k + 2 < bytes.size(); k += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[k]) << 16 |
                       static_cast<unsigned char>(bytes[k + 1]) << 8 |
                       static_cast<unsigned char>(bytes[k + 2]);
    for (const int shift : {18, 12, 6, 0}) encoded += kAlphabet[(v >> shift) & 63];
  }
  if (k < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[k]) << 16;
    if (k + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[k + 1]) << 8;
    encoded += kAlphabet[(v >> 18) & 63];
    encoded += kAlphabet[(v >> 12) & 63];
    encoded += k + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    encoded += '=';
  }
  return encoded;
}

std::string Parameter(const StudyRun& run) { return IsAdaptive(run.method) ? "rtol" : "h"; }

std::string ReferenceText(const ReferenceReport& reference) {
  std::string text = "Reference: " + reference.kind + ", " + reference.description + ".";
  if (reference.cross_check.empty()) return text + " No second reference to cross-check it.";
  text += " Cross-check: " + reference.cross_check + "; the two differ by at most " +
          StudyNumber(reference.agreement) + " over the grid, ";
  text += std::isfinite(reference.bound)
              ? (reference.agree ? "within" : "BEYOND") + std::string(" the study's bound ") +
                    StudyNumber(reference.bound) +
                    " (2 × the sum of their error estimates + 1000 ε × the solution's size)."
              : std::string("with no bound (no error estimate of the reference).");
  return text;
}

// Outcome tables, one per ladder: methods down, rungs across; reasons as
// numbered notes shared by equal texts.
struct OutcomeTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::vector<OutcomeTable> OutcomeTables(const StudyResult& result,
                                        std::vector<std::string>& notes) {
  std::vector<OutcomeTable> tables;
  for (const bool adaptive : {true, false}) {
    std::vector<double> rungs;
    for (const StudyRun& run : result.runs)
      if (IsAdaptive(run.method) == adaptive &&
          std::find(rungs.begin(), rungs.end(), run.parameter) == rungs.end())
        rungs.push_back(run.parameter);
    if (rungs.empty()) continue;
    std::sort(rungs.rbegin(), rungs.rend());
    OutcomeTable table;
    table.header.push_back("method");
    for (const double rung : rungs)
      table.header.push_back((adaptive ? "rtol = " : "h = ") + StudyNumber(rung));
    if (!adaptive && result.stiffness > 0) {
      std::vector<std::string> row{"h·ρ"};
      for (const double rung : rungs) row.push_back(StudyNumber(rung * result.stiffness));
      table.rows.push_back(row);
    }
    for (const StudyMethod method : kAllStudyMethods) {
      if (IsAdaptive(method) != adaptive) continue;
      std::vector<std::string> row{ToString(method)};
      for (const double rung : rungs) {
        const auto run = std::find_if(
            result.runs.begin(), result.runs.end(),
            [&](const StudyRun& r) { return r.method == method && r.parameter == rung; });
        if (run == result.runs.end()) {
          row.push_back("");
          continue;
        }
        std::string cell = ToString(run->outcome);
        if (!run->reason.empty()) {
          auto note = std::find(notes.begin(), notes.end(), run->reason);
          if (note == notes.end()) note = notes.insert(notes.end(), run->reason);
          cell += " (" + std::to_string(note - notes.begin() + 1) + ")";
        }
        row.push_back(cell);
      }
      if (row.size() > 1 && std::any_of(row.begin() + 1, row.end(),
                                        [](const std::string& cell) { return !cell.empty(); }))
        table.rows.push_back(row);
    }
    tables.push_back(table);
  }
  return tables;
}

std::string MarkdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows) {
  std::string text = "|";
  for (const std::string& cell : header) text += " " + cell + " |";
  text += "\n|";
  for (std::size_t k = 0; k < header.size(); ++k) text += "---|";
  text += "\n";
  for (const auto& row : rows) {
    text += "|";
    for (const std::string& cell : row) text += " " + cell + " |";
    text += "\n";
  }
  return text;
}

std::string HtmlTable(const std::string& id, const std::vector<std::string>& header,
                      const std::vector<std::vector<std::string>>& rows) {
  std::string html = "<table id=\"" + id + "\">\n<thead><tr>";
  for (const std::string& cell : header) html += "<th>" + Escape(cell) + "</th>";
  html += "</tr></thead>\n<tbody>\n";
  for (const auto& row : rows) {
    html += "<tr>";
    for (const std::string& cell : row) html += "<td>" + Escape(cell) + "</td>";
    html += "</tr>\n";
  }
  return html + "</tbody></table>\n";
}

std::vector<std::string> SlopeHeader() {
  return {"method", "fitted order", "rungs", "decades of h or rtol"};
}

std::vector<std::vector<std::string>> SlopeRows(const StudyResult& result) {
  std::vector<std::vector<std::string>> rows;
  for (const Slope& slope : result.slopes)
    rows.push_back(
        {ToString(slope.method) + (IsAdaptive(slope.method) ? " (error vs rtol)" : " (error vs h)"),
         StudyNumber(slope.slope), std::to_string(slope.rungs), StudyNumber(slope.decades)});
  return rows;
}

std::string OrdersText(const StudyResult& result) {
  return "Slope of log max error against log h (time-stepping) or log rtol, fitted over each "
         "method's finest neighbouring rungs (" +
         std::to_string(kFitRungs) + " at most) that converged with an error above the floor " +
         StudyNumber(result.error_floor) +
         " (10 × the reference's error estimate, at least 1000 ε × the solution's size), "
         "for time-stepping above " +
         StudyNumber(result.stepping_error_floor) +
         " (at least 10 × max(1, horizon) × the VI solver's tolerance: below it the error "
         "measures the steps' VI solves); fewer than 3 such rungs give none.";
}

// Converged runs whose error is above the floor: below it the error
// measures the reference, not the run (the reference run itself is at 0).
bool OnChart(const StudyResult& result, const StudyRun& run) {
  return run.outcome == RunOutcome::kConverged && run.max_error > result.error_floor;
}

std::vector<WorkPoint> Points(const StudyResult& result, StudyMethod method, bool seconds) {
  std::vector<WorkPoint> points;
  for (const StudyRun& run : result.runs)
    if (OnChart(result, run) && run.method == method)
      points.push_back(
          {run.max_error, seconds ? run.timing.seconds : static_cast<double>(run.rhs_evals)});
  return points;
}

std::vector<std::string> CostHeader(const StudyResult& result) {
  std::vector<std::string> header{"method"};
  for (const double target : kCostTargets)
    header.push_back("error " + StudyNumber(target * result.reference.scale) + ": s / RHS evals");
  return header;
}

std::vector<std::vector<std::string>> CostRows(const StudyResult& result) {
  std::vector<std::vector<std::string>> rows;
  for (const StudyMethod method : kAllStudyMethods) {
    const std::vector<WorkPoint> by_time = Points(result, method, true);
    if (by_time.empty()) continue;
    std::vector<std::string> row{ToString(method)};
    for (const double target : kCostTargets) {
      const double error = target * result.reference.scale;
      const CostAtError time = CostAt(by_time, error);
      const CostAtError evals = CostAt(Points(result, method, false), error);
      row.push_back(std::isfinite(time.interpolated)
                        ? StudyNumber(time.interpolated) + " / " + StudyNumber(evals.interpolated)
                        : "not reached (best " + StudyNumber(time.best_error) + ")");
    }
    rows.push_back(row);
  }
  return rows;
}

std::string LoadAverage() {
  std::ifstream file("/proc/loadavg");
  std::string one, five, fifteen;
  file >> one >> five >> fifteen;
  return file ? one + " " + five + " " + fifteen : "unknown";
}

}  // namespace

std::string StudyNumber(double value) {
  if (std::isnan(value)) return "";
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

std::string StudyCsvHeader() {
  return "method,parameter,value,atol,outcome,reason,status,max_error,grid_error,switch_error,"
         "event_time_error,switches,mode_sequence,steps,rejected_steps,rhs_evals,vi_solves,"
         "certified,vi_ratio,ode_ratio,seconds,repeats";
}

std::vector<std::string> StudyCsvFields(const StudyRun& run) {
  return {ToString(run.method),
          Parameter(run),
          StudyNumber(run.parameter),
          IsAdaptive(run.method) ? StudyNumber(run.atol) : "",
          ToString(run.outcome),
          run.reason,
          run.status,
          StudyNumber(run.max_error),
          StudyNumber(run.grid_error),
          StudyNumber(run.switch_error),
          StudyNumber(run.event_time_error),
          run.switches < 0 ? "" : std::to_string(run.switches),
          run.mode_sequence,
          std::to_string(run.steps),
          std::to_string(run.rejected_steps),
          std::to_string(run.rhs_evals),
          std::to_string(run.vi_solves),
          run.certificate_evaluated ? (run.certified ? "yes" : "no") : "",
          StudyNumber(run.vi_ratio),
          StudyNumber(run.ode_ratio),
          StudyNumber(run.timing.seconds),
          std::to_string(run.timing.repeats)};
}

std::string StudyCsv(const StudyResult& result) {
  std::string csv = StudyCsvHeader() + "\n";
  for (const StudyRun& run : result.runs) {
    const std::vector<std::string> fields = StudyCsvFields(run);
    for (std::size_t k = 0; k < fields.size(); ++k) csv += (k ? "," : "") + CsvField(fields[k]);
    csv += "\n";
  }
  return csv;
}

std::string StabilityMarkdown(const StudyResult& result) {
  std::ostringstream text;
  text << "# Study of " << result.title << ": stability\n\n"
       << ReferenceText(result.reference) << "\n\n";
  if (result.stiffness > 0)
    text << "ρ(∂f/∂x) at t = 0 is " << StudyNumber(result.stiffness)
         << ": explicit Euler (θ = 1) is stable on a real eigenvalue −ρ only for h·ρ ≤ 2, "
            "backward Euler (θ = 0) for every h.\n\n";
  std::vector<std::string> notes;
  const std::vector<OutcomeTable> tables = OutcomeTables(result, notes);
  for (const OutcomeTable& table : tables) {
    text << "## " << (table.header[1].rfind("rtol", 0) == 0 ? "Tolerance ladder" : "Step ladder")
         << "\n\n"
         << MarkdownTable(table.header, table.rows) << "\n";
  }
  if (!notes.empty()) {
    text << "Notes:\n\n";
    for (std::size_t k = 0; k < notes.size(); ++k) text << k + 1 << ". " << notes[k] << "\n";
    text << "\n";
  }
  text << "## Orders\n\n"
       << OrdersText(result) << "\n\n"
       << MarkdownTable(SlopeHeader(), SlopeRows(result));
  return text.str();
}

nlohmann::ordered_json StudyJson(const StudyResult& result, int jobs) {
  const ReferenceReport& reference = result.reference;
  nlohmann::ordered_json json;
  json["title"] = result.title;
  json["reference"] = {{"kind", reference.kind},
                       {"description", reference.description},
                       {"error_estimate", NumberToJson(reference.error_estimate)},
                       {"cross_check", reference.cross_check},
                       {"agreement", NumberToJson(reference.agreement)},
                       {"bound", NumberToJson(reference.bound)},
                       {"agree", reference.agree},
                       {"switch_times", reference.switch_times},
                       {"modes_compared", reference.modes_known},
                       {"scale", reference.scale}};
  json["grid_points"] = result.grid_points;
  json["error_floor"] = result.error_floor;
  json["stepping_error_floor"] = result.stepping_error_floor;
  json["stiffness"] = NumberToJson(result.stiffness);
  nlohmann::ordered_json slopes = nlohmann::ordered_json::array();
  for (const Slope& slope : result.slopes)
    slopes.push_back({{"method", ToString(slope.method)},
                      {"slope", NumberToJson(slope.slope)},
                      {"rungs", slope.rungs},
                      {"decades", slope.decades}});
  json["slopes"] = slopes;
  nlohmann::ordered_json costs = nlohmann::ordered_json::array();
  for (const StudyMethod method : kAllStudyMethods) {
    const std::vector<WorkPoint> by_time = Points(result, method, true);
    if (by_time.empty()) continue;
    for (const double target : kCostTargets) {
      const double error = target * reference.scale;
      costs.push_back(
          {{"method", ToString(method)},
           {"error", error},
           {"seconds", NumberToJson(CostAt(by_time, error).interpolated)},
           {"rhs_evals", NumberToJson(CostAt(Points(result, method, false), error).interpolated)}});
    }
  }
  json["cost_at_error"] = costs;
  json["runs"] = result.runs.size();
  json["machine"] = {{"cores", std::thread::hardware_concurrency()},
                     {"jobs", jobs},
                     {"load_average", LoadAverage()}};
  return json;
}

std::string WorkPrecisionScript(const StudyResult& result) {
  std::ostringstream script;
  script.precision(10);
  std::vector<StudyMethod> drawn;
  for (const StudyMethod method : kAllStudyMethods) {
    const std::vector<WorkPoint> points = Points(result, method, true);
    if (points.empty()) continue;
    drawn.push_back(method);
    script << "$m" << drawn.size() << " << EOD\n";
    for (const StudyRun& run : result.runs)
      if (OnChart(result, run) && run.method == method)
        script << run.max_error << " " << run.timing.seconds << " " << run.rhs_evals << "\n";
    script << "EOD\n";
  }
  std::string title =
      result.title + ": work-precision against the " + result.reference.kind + " reference";
  std::replace(title.begin(), title.end(), '\'', ' ');
  const auto panels = [&]() {
    std::ostringstream p;
    p << "set multiplot layout 1,2 title '" << title << "'\n";
    for (const auto& [column, label] : {std::pair<int, const char*>{2, "wall time [s]"},
                                        std::pair<int, const char*>{3, "RHS evaluations"}}) {
      p << "set xlabel 'max error'\nset ylabel '" << label << "'\n";
      if (drawn.empty()) {
        p << "set label 1 'no converged run above the error floor' at graph 0.2, graph 0.5\nplot "
             "[1e-12:1] [1:10] 1/0 notitle\n";
        continue;
      }
      p << "plot ";
      for (std::size_t k = 0; k < drawn.size(); ++k)
        p << (k ? ", " : "") << "$m" << k + 1 << " using 1:($" << column << " > 0 ? $" << column
          << " : 1/0) with linespoints lw 1.5 title '" << ToString(drawn[k]) << "'";
      p << "\n";
    }
    p << "unset multiplot\n";
    return p.str();
  };
  script << "set logscale xy\nset format x '%.0e'\nset format y '%.0e'\nset grid\n"
            "set key top right font ',9'\n"
            "set terminal pngcairo size 1400,600 noenhanced\nset output 'work_precision.png'\n"
         << panels()
         << "set terminal svg size 1400,600 noenhanced\nset output 'work_precision.svg'\n"
         << panels() << "unset output\n";
  return script.str();
}

std::string StudyHtml(const StudyResult& result, const std::string& svg) {
  std::ostringstream html;
  const std::string title = "Study of " + result.title;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
       << Escape(title) << "</title>\n<style>\n"
       << "body{font-family:sans-serif;margin:2em;max-width:1500px}"
          "table{border-collapse:collapse;margin:1em 0;font-size:90%}"
          "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}"
          "td:first-child,th:first-child{text-align:left}"
          "img{max-width:100%;border:1px solid #ddd}\n"
       << "</style>\n</head>\n<body>\n<h1>" << Escape(title) << "</h1>\n"
       << "<p id=\"reference\">" << Escape(ReferenceText(result.reference)) << "</p>\n"
       << "<h2>Work-precision</h2>\n<figure>\n<img id=\"work-precision\" alt=\"work-precision "
          "chart\" src=\"data:image/svg+xml;base64,"
       << Base64(svg)
       << "\" onload=\"this.dataset.loaded='yes'\" onerror=\"this.dataset.loaded='no'\">\n"
       << "<figcaption>Max error over the grid and the switch points against wall time (median "
          "of repeats) and RHS evaluations; converged runs above the error floor only."
          "</figcaption>\n</figure>\n"
       << "<h2>Cost at a given error</h2>\n<p>Interpolated on each method's Pareto front "
          "(seconds / RHS evaluations).</p>\n"
       << HtmlTable("cost", CostHeader(result), CostRows(result)) << "<h2>Orders</h2>\n<p>"
       << Escape(OrdersText(result)) << "</p>\n"
       << HtmlTable("slopes", SlopeHeader(), SlopeRows(result));
  std::vector<std::string> notes;
  const std::vector<OutcomeTable> tables = OutcomeTables(result, notes);
  html << "<h2>Stability</h2>\n";
  for (std::size_t k = 0; k < tables.size(); ++k)
    html << HtmlTable(tables[k].header[1].rfind("rtol", 0) == 0 ? "stability-rtol" : "stability-h",
                      tables[k].header, tables[k].rows);
  if (!notes.empty()) {
    html << "<ol id=\"notes\">\n";
    for (const std::string& note : notes) html << "<li>" << Escape(note) << "</li>\n";
    html << "</ol>\n";
  }
  std::vector<std::string> header;
  std::stringstream columns(StudyCsvHeader());
  for (std::string column; std::getline(columns, column, ',');) header.push_back(column);
  std::vector<std::vector<std::string>> rows;
  for (const StudyRun& run : result.runs) rows.push_back(StudyCsvFields(run));
  html << "<h2>Every run (study.csv)</h2>\n"
       << HtmlTable("runs", header, rows) << "</body>\n</html>\n";
  return html.str();
}

}  // namespace dvi::dvisim
