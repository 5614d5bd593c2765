// SPDX-License-Identifier: Apache-2.0
#include "exact_solution.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "expression.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {
namespace {

using nlohmann::json;

[[noreturn]] void Refuse(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

std::string Entry(const std::string& path, std::size_t k) {
  return path + "[" + std::to_string(k) + "]";
}

std::string Text(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.10g", value);
  return text;
}

std::string VectorText(const Eigen::VectorXd& x) {
  std::string text = "(";
  for (Eigen::Index i = 0; i < x.size(); ++i) text += (i > 0 ? ", " : "") + Text(x(i));
  return text + ")";
}

void OnlyFields(const json& object, const std::string& path,
                const std::vector<std::string>& known) {
  if (!object.is_object()) Refuse(path, "expected an object, got " + Describe(object));
  for (const auto& item : object.items())
    if (std::find(known.begin(), known.end(), item.key()) == known.end())
      Refuse(path, "unknown field \"" + item.key() + "\" (expected " +
                       (known.size() == 2 ? known[0] + " or " + known[1]
                                          : known[0] + ", " + known[1] + " or " + known[2]) +
                       ")");
}

// A string, or a number standing for itself (as in the problem's expressions).
GiNaC::ex ParseEntry(const json& value, const ExpressionVariables& variables,
                     const std::string& path) {
  if (value.is_number()) {
    char text[40];
    std::snprintf(text, sizeof(text), "%.17g", value.get<double>());
    return variables.Parse(text, path);
  }
  if (!value.is_string())
    Refuse(path, "expected an expression in t (a string or a number), got " + Describe(value));
  return variables.Parse(value.get<std::string>(), path);
}

Eigen::VectorXd Evaluate(const ExpressionTape& tape, double t) {
  Eigen::VectorXd out(tape.size());
  std::vector<double> scratch = tape.NewScratch();
  tape.Evaluate(t, Eigen::VectorXd(), Eigen::VectorXd(), out.data(), scratch);
  return out;
}

}  // namespace

ExactSolution::ExactSolution(const json& block, const std::string& path, int n, double horizon,
                             const Eigen::VectorXd& x0) {
  OnlyFields(block, path, {"params", "pieces"});
  std::vector<std::pair<std::string, double>> params;
  if (const auto it = block.find("params"); it != block.end()) {
    if (!it->is_object()) Refuse(path + ".params", "expected an object, got " + Describe(*it));
    for (const auto& item : it->items())
      params.emplace_back(item.key(),
                          ReadNumber(item.value(), path + ".params." + item.key(), false));
  }
  // t and the parameters only: an exact solution is a function of time.
  const ExpressionVariables variables(0, 0, params, path + ".params");
  const std::string pieces_path = path + ".pieces";
  const json& pieces = RequireField(block, "pieces", path);
  if (!pieces.is_array() || pieces.empty())
    Refuse(pieces_path, "expected a non-empty array of pieces, got " + Describe(pieces));
  double from = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const std::string piece_path = Entry(pieces_path, k);
    const json& piece = pieces[k];
    OnlyFields(piece, piece_path, {"to", "x"});
    const bool last = k + 1 == pieces.size();
    const auto to = piece.find("to");
    if (last && to != piece.end())
      Refuse(piece_path + ".to", "the last piece runs to the horizon; leave \"to\" out");
    if (!last) {
      if (to == piece.end())
        Refuse(piece_path, "missing field \"to\" (the switch time where the next piece starts)");
      const GiNaC::ex time = ParseEntry(*to, variables, piece_path + ".to");
      if (time.has(variables.t()))
        Refuse(piece_path + ".to", "a switch time is a number, it must not depend on t");
      const double value = Evaluate(ExpressionTape({time}, variables, piece_path + ".to"), 0)(0);
      if (!(value > from && value < horizon))
        Refuse(piece_path + ".to", "switch time " + Text(value) + " is not in (" + Text(from) +
                                       ", horizon " + Text(horizon) +
                                       "): the switch times must increase within the horizon");
      switch_times_.push_back(value);
    }
    const std::string x_path = piece_path + ".x";
    const json& x = RequireField(piece, "x", piece_path);
    if (!x.is_array() || x.size() != static_cast<std::size_t>(n))
      Refuse(x_path, "expected " + std::to_string(n) + " expressions in t (one per state), got " +
                         Describe(x));
    std::vector<GiNaC::ex> expressions;
    for (std::size_t i = 0; i < x.size(); ++i)
      expressions.push_back(ParseEntry(x[i], variables, Entry(x_path, i)));
    pieces_.push_back(std::make_shared<const ExpressionTape>(expressions, variables, x_path));
    // x is continuous: this piece starts where the last one ended (x0 at 0).
    const Eigen::VectorXd start = Evaluate(*pieces_.back(), from);
    const Eigen::VectorXd expected = k == 0 ? x0 : Evaluate(*pieces_[k - 1], from);
    const double scale = std::max(1.0, expected.lpNorm<Eigen::Infinity>());
    if (!start.allFinite() ||
        !((start - expected).lpNorm<Eigen::Infinity>() <= kContinuityTolerance * scale))
      Refuse(x_path, "gives x(" + Text(from) + ") = " + VectorText(start) + ", but " +
                         (k == 0 ? "x0 = " : "the previous piece ends at ") + VectorText(expected) +
                         " (x is continuous)");
    if (!last) from = switch_times_.back();
  }
}

Eigen::VectorXd ExactSolution::State(double t) const {
  const auto piece = std::lower_bound(switch_times_.begin(), switch_times_.end(), t);
  return Evaluate(*pieces_[static_cast<std::size_t>(piece - switch_times_.begin())], t);
}

}  // namespace dvi::dvisim
