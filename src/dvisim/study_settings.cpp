// SPDX-License-Identifier: Apache-2.0
#include "study_settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "json_reading.hpp"
#include "problem_file.hpp"

namespace dvi::dvisim {
namespace {

using nlohmann::json;

// A non-empty array whose entries `read` turns into values, no value twice.
template <typename Value>
std::vector<Value> ReadList(const json& value, const std::string& path,
                            const std::function<Value(const json&, const std::string&)>& read) {
  if (!value.is_array() || value.empty())
    throw InputError(path + ": expected a non-empty array, got " + Describe(value));
  std::vector<Value> list;
  for (std::size_t k = 0; k < value.size(); ++k) {
    const std::string entry = path + "[" + std::to_string(k) + "]";
    list.push_back(read(value[k], entry));
    if (std::find(list.begin(), list.end() - 1, list.back()) != list.end() - 1)
      throw InputError(entry + ": repeats an earlier entry");
  }
  return list;
}

}  // namespace

std::string ShortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

std::string ToString(StudyMethod method) {
  switch (method) {
    case StudyMethod::kEvent:
      return "event";
    case StudyMethod::kAuto:
      return "auto";
    case StudyMethod::kSteppingTheta0:
      return "stepping-theta0";
    case StudyMethod::kSteppingHalf:
      return "stepping-theta0.5";
    case StudyMethod::kSteppingTheta1:
      return "stepping-theta1";
    case StudyMethod::kCvode:
      return "cvode";
    case StudyMethod::kDopri5:
      return "dopri5";
    case StudyMethod::kRosenbrock4:
      return "rosenbrock4";
  }
  return "?";
}

bool IsAdaptive(StudyMethod method) {
  return method != StudyMethod::kSteppingTheta0 && method != StudyMethod::kSteppingHalf &&
         method != StudyMethod::kSteppingTheta1;
}

bool IsImplicitRhsBaseline(StudyMethod method) {
  return method == StudyMethod::kCvode || method == StudyMethod::kDopri5 ||
         method == StudyMethod::kRosenbrock4;
}

void CheckStepCount(double h, double horizon, long max_steps, const std::string& field) {
  const double steps = std::ceil(horizon / h);
  if (steps > static_cast<double>(max_steps))
    throw InputError(field + ": h = " + ShortNumber(h) + " asks for " + ShortNumber(steps) +
                     " steps over the horizon " + ShortNumber(horizon) +
                     ", more than method.max_steps = " + std::to_string(max_steps) +
                     " allows; take a larger h, or raise method.max_steps");
}

StudySettings ReadStudySettings(const json& block, const std::string& path, double horizon,
                                long max_steps) {
  if (!block.is_object()) throw InputError(path + ": expected an object, got " + Describe(block));
  StudySettings settings;
  for (const auto& item : block.items()) {
    const std::string field = path + "." + item.key();
    if (item.key() == "rtol") {
      settings.rtol = ReadList<double>(item.value(), field, ReadTolerance);
      std::sort(settings.rtol.rbegin(), settings.rtol.rend());
    } else if (item.key() == "h") {
      settings.h =
          ReadList<double>(item.value(), field, [&](const json& value, const std::string& entry) {
            const double h = ReadNumber(value, entry, false);
            if (!(h > 0 && h <= horizon))
              throw InputError(entry + ": expected a step in (0, horizon] = (0, " +
                               ShortNumber(horizon) + "], got " + Describe(value));
            CheckStepCount(h, horizon, max_steps, entry);
            return h;
          });
      std::sort(settings.h.rbegin(), settings.h.rend());
    } else if (item.key() == "methods") {
      settings.methods = ReadList<StudyMethod>(
          item.value(), field, [](const json& value, const std::string& entry) {
            std::string names;
            for (const StudyMethod method : kAllStudyMethods) {
              if (value.is_string() && value.get<std::string>() == ToString(method)) return method;
              names += (names.empty() ? "" : ", ") + ToString(method);
            }
            throw InputError(entry + ": unknown method " + Describe(value) + " (expected " + names +
                             ")");
          });
    } else {
      throw InputError(path + ": unknown field \"" + item.key() +
                       "\" (expected rtol, h or methods)");
    }
  }
  return settings;
}

}  // namespace dvi::dvisim
