// SPDX-License-Identifier: Apache-2.0
#include "scene_sources.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "expression.hpp"
#include "scene_fields.hpp"

namespace dvi::dvisim {
namespace {

using nlohmann::json;

std::string Text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  std::ostringstream text;
  text.precision(17);
  text << value.get<double>();
  return text.str();
}

std::string Number(double value) {
  std::ostringstream text;
  text.precision(10);
  text << value;
  return text.str();
}

// A time given as a number or an expression in the params (not in t).
double ReadConstantTime(const json& value, const std::string& path,
                        const ExpressionVariables& variables) {
  if (!value.is_string() && !value.is_number())
    Fail(path, "expected a time (a number or an expression in the params), got " + Describe(value));
  const ExpressionFunction expression({Text(value)}, variables, path);
  if (expression.expressions()[0].has(variables.t()))
    Fail(path, "\"" + Text(value) + "\" depends on t; a breakpoint is a fixed time");
  Eigen::VectorXd out(1);
  const Eigen::VectorXd none;
  expression.Function()(0, none, none, out);
  if (!std::isfinite(out[0])) Fail(path, "is " + Number(out[0]) + ", not a finite time");
  return out[0];
}

}  // namespace

void ReadSourceVector(const json& value, const std::string& path, int size,
                      const SceneParams& params, const std::string& params_path,
                      Eigen::VectorXd& constant, TimeSource& source, TimeSource* rate) {
  const bool expressions = value.is_array() && std::any_of(value.begin(), value.end(),
                                                           [](const json& v) { return v.is_string(); });
  if (!expressions) {
    constant = ReadVector(value, path, false, size);
    return;
  }
  if (value.size() != static_cast<std::size_t>(size))
    Fail(path, "has " + std::to_string(value.size()) + " entries, expected " + std::to_string(size));
  std::vector<std::string> texts;
  for (std::size_t k = 0; k < value.size(); ++k) {
    if (!value[k].is_string() && !value[k].is_number())
      Fail(Indexed(path, k), "expected a number or an expression in t, got " + Describe(value[k]));
    texts.push_back(Text(value[k]));
  }
  const ExpressionVariables variables(0, 0, params, params_path);
  const ExpressionFunction function(texts, variables, path);
  constant = Eigen::VectorXd::Zero(size);
  const auto as_source = [](TimeStateFunction g) -> TimeSource {
    return [g = std::move(g)](double t, Eigen::VectorXd& out) {
      static const Eigen::VectorXd none;
      g(t, none, none, out);
    };
  };
  source = as_source(function.Function());
  if (rate) *rate = as_source(function.TimeDerivative());
}

std::vector<double> ReadBreakpoints(const json& value, const std::string& path,
                                    const SceneParams& params, const std::string& params_path,
                                    double horizon) {
  const ExpressionVariables variables(0, 0, params, params_path);
  const std::string range = "(0, horizon] = (0, " + Number(horizon) + "]";
  std::vector<double> times;
  if (value.is_object()) {
    RejectUnknownFields(value, path, {"period", "offset"});
    const std::string period_path = Field(path, "period");
    const double period =
        ReadConstantTime(RequireField(value, "period", path), period_path, variables);
    if (!(period > 0)) Fail(period_path, "is " + Number(period) + "; a period is positive");
    const json* offset_json = FindField(value, "offset");
    const double offset =
        offset_json ? ReadConstantTime(*offset_json, Field(path, "offset"), variables) : 0.0;
    if (!(offset >= 0 && offset < horizon))
      Fail(Field(path, "offset"), "is " + Number(offset) + ", outside [0, horizon)");
    const double count = std::floor((horizon - offset) / period) + 1;
    if (count > static_cast<double>(kMaxBreakpoints))
      Fail(period_path, "gives " + Number(count) + " breakpoints over the horizon, more than " +
                            std::to_string(kMaxBreakpoints) + " (a unit mistake?)");
    for (long k = 0; k < static_cast<long>(count); ++k) {
      const double t = offset + static_cast<double>(k) * period;
      if (t > 0 && t <= horizon) times.push_back(t);
    }
    return times;
  }
  if (!value.is_array())
    Fail(path, "expected an array of times or {\"period\": T, \"offset\": t1}, got " +
                   Describe(value));
  if (value.size() > static_cast<std::size_t>(kMaxBreakpoints))
    Fail(path, "has " + std::to_string(value.size()) + " entries, more than " +
                   std::to_string(kMaxBreakpoints));
  for (std::size_t k = 0; k < value.size(); ++k) {
    const std::string entry = Indexed(path, k);
    const double t = ReadConstantTime(value[k], entry, variables);
    if (!(t > 0 && t <= horizon)) Fail(entry, "is " + Number(t) + ", outside " + range);
    if (k > 0 && !(t > times.back()))
      Fail(entry, "is " + Number(t) + ", not after " + Indexed(path, k - 1) + " = " +
                      Number(times.back()) + " (breakpoints are strictly ascending)");
    times.push_back(t);
  }
  return times;
}

}  // namespace dvi::dvisim
