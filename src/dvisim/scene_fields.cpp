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

}  // namespace dvi::dvisim
