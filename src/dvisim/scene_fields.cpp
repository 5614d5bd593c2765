// SPDX-License-Identifier: Apache-2.0
#include "scene_fields.hpp"

#include <algorithm>

namespace dvi::dvisim {

using nlohmann::json;

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

std::string Field(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string Indexed(const std::string& path, std::size_t k) {
  return path + "[" + std::to_string(k) + "]";
}

const json* FindField(const json& object, const std::string& key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

void RejectUnknownFields(const json& object, const std::string& path,
                         const std::vector<std::string>& known, const std::string& context) {
  for (const auto& item : object.items()) {
    if (std::find(known.begin(), known.end(), item.key()) != known.end()) continue;
    std::string list;
    for (const std::string& key : known) list += (list.empty() ? "" : ", ") + key;
    Fail(path.empty() ? "(file)" : path,
         "unknown field \"" + item.key() + "\"" + context + " (expected " + list + ")");
  }
}

void RequireObject(const json& value, const std::string& path) {
  if (!value.is_object()) Fail(path, "expected an object, got " + Describe(value));
}

IntegrationMethod ReadSceneMethod(const std::string& name, const std::string& path) {
  for (const IntegrationMethod method :
       {IntegrationMethod::kAuto, IntegrationMethod::kTimeStepping, IntegrationMethod::kEventDriven,
        IntegrationMethod::kBoundaryValue})
    if (name == ToString(method)) return method;
  Fail(path, "unknown method " + Describe(nlohmann::json(name)) +
                 " (expected auto, stepping, event or bvp)");
}

double ReadUnitInterval(const json& value, const std::string& path) {
  const double x = ReadNumber(value, path, false);
  if (!(x >= 0 && x <= 1)) Fail(path, "expected a number in [0, 1], got " + Describe(value));
  return x;
}

double ReadPositive(const json& value, const std::string& path) {
  const double x = ReadNumber(value, path, false);
  if (!(x > 0)) Fail(path, "expected a number > 0, got " + Describe(value));
  return x;
}

long ReadCount(const json& value, const std::string& path) {
  if (!value.is_number_integer() || value.get<long>() < 1)
    Fail(path, "expected an integer ≥ 1, got " + Describe(value));
  return value.get<long>();
}

void CheckShape(const MatrixField& M, const std::string& path, Eigen::Index rows,
                Eigen::Index cols) {
  if (M.rows() != rows || M.cols() != cols)
    Fail(path, "is " + std::to_string(M.rows()) + "x" + std::to_string(M.cols()) + ", expected " +
                   std::to_string(rows) + "x" + std::to_string(cols));
}

SparseMatrix ToSparse(const MatrixField& M) {
  return M.is_sparse ? M.sparse : SparseMatrix(M.dense.sparseView());
}

}  // namespace dvi::dvisim
