// SPDX-License-Identifier: Apache-2.0
#include "sweep_file.hpp"

#include <algorithm>
#include <filesystem>

#include "json_reading.hpp"

namespace dvi::dvisim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A pointer the sweep may set: syntactically a JSON pointer, not the root.
void CheckPointer(const std::string& pointer, const std::string& path) {
  if (pointer.empty() || pointer[0] != '/')
    throw InputError(path + ": expected a JSON pointer into the scene such as \"/x0/0\" or "
                            "\"/problem/params/a\", got \"" + pointer + "\"");
  try {
    (void)json::json_pointer(pointer);
  } catch (const json::exception& error) {
    throw InputError(path + ": \"" + pointer + "\" is not a JSON pointer (" + error.what() + ")");
  }
}

// Sets scene[pointer] = value where the parent exists (see MemberScene).
void Apply(json& scene, const std::string& pointer, const json& value, const std::string& path) {
  const json::json_pointer target(pointer);
  const json::json_pointer parent = target.parent_pointer();
  if (!scene.contains(parent))
    throw InputError(path + ": \"" + parent.to_string() + "\" is not in the scene");
  json& container = scene.at(parent);
  const std::string key = target.back();
  if (container.is_array()) {
    std::size_t index = 0;
    try {
      std::size_t used = 0;
      index = std::stoul(key, &used);
      if (used != key.size()) throw std::invalid_argument(key);
    } catch (const std::exception&) {
      throw InputError(path + ": \"" + key + "\" is not an index of the array at \"" +
                       parent.to_string() + "\"");
    }
    if (index >= container.size())
      throw InputError(path + ": \"" + parent.to_string() + "\" has " +
                       std::to_string(container.size()) + " entries, no index " + key);
    container[index] = value;
  } else if (container.is_object()) {
    container[key] = value;
  } else {
    throw InputError(path + ": \"" + parent.to_string() + "\" is " + Describe(container) +
                     ", not an object or an array");
  }
}

}  // namespace

Sweep ParseSweep(const std::string& text, const std::string& path) {
  const json file = ParseJson(text);
  if (!file.is_object()) throw InputError("sweep: expected an object, got " + Describe(file));
  for (const auto& [key, value] : file.items())
    if (key != "scene" && key != "grid" && key != "members" && key != "output" &&
        key != "description")
      throw InputError("sweep." + key +
                       ": unknown field (expected scene, grid, members, output, description)");
  Sweep sweep;
  const json& scene = RequireField(file, "scene", "sweep");
  if (scene.is_string()) {
    const fs::path scene_path = fs::path(path).parent_path() / scene.get<std::string>();
    sweep.base_source = scene_path.string();
    sweep.base = ParseJson(ReadTextFile(scene_path.string()));
  } else if (scene.is_object()) {
    sweep.base_source = "sweep.scene";
    sweep.base = scene;
  } else {
    throw InputError("sweep.scene: expected a scene file name or a scene object, got " +
                     Describe(scene));
  }

  std::vector<std::vector<std::pair<std::string, json>>> listed{{}};
  if (file.contains("members")) {
    const json& members = file["members"];
    if (!members.is_array() || members.empty())
      throw InputError("sweep.members: expected a non-empty list of overrides, got " +
                       Describe(members));
    listed.clear();
    for (std::size_t k = 0; k < members.size(); ++k) {
      const std::string where = "sweep.members[" + std::to_string(k) + "]";
      if (!members[k].is_object())
        throw InputError(where + ": expected an object of overrides {\"/pointer\": value}, got " +
                         Describe(members[k]));
      auto& overrides = listed.emplace_back();
      for (const auto& [pointer, value] : members[k].items()) {
        CheckPointer(pointer, where + "[\"" + pointer + "\"]");
        overrides.emplace_back(pointer, value);
      }
    }
  }

  std::vector<std::pair<std::string, json>> grid;
  if (file.contains("grid")) {
    const json& axes = file["grid"];
    if (!axes.is_object() || axes.empty())
      throw InputError("sweep.grid: expected an object {\"/pointer\": [values]}, got " +
                       Describe(axes));
    for (const auto& [pointer, values] : axes.items()) {
      const std::string where = "sweep.grid[\"" + pointer + "\"]";
      CheckPointer(pointer, where);
      if (!values.is_array() || values.empty())
        throw InputError(where + ": expected a non-empty list of values, got " + Describe(values));
      grid.emplace_back(pointer, values);
    }
  }

  std::size_t count = listed.size();
  for (const auto& [pointer, values] : grid) {
    if (values.size() > kMaxSweepMembers / count)
      throw InputError("sweep: more than " + std::to_string(kMaxSweepMembers) +
                       " members (the grid's sizes times the members' count)");
    count *= values.size();
  }
  sweep.members.reserve(count);
  for (const auto& overrides : listed) {
    const std::size_t points = count / listed.size();
    for (std::size_t point = 0; point < points; ++point) {
      auto& member = sweep.members.emplace_back(overrides);
      // Mixed radix, the first key slowest.
      std::size_t rest = point, stride = points;
      for (const auto& [pointer, values] : grid) {
        stride /= values.size();
        member.emplace_back(pointer, values[rest / stride]);
        rest %= stride;
      }
    }
  }
  for (const auto& member : sweep.members)
    for (const auto& override_entry : member)
      if (std::find(sweep.columns.begin(), sweep.columns.end(), override_entry.first) ==
          sweep.columns.end())
        sweep.columns.push_back(override_entry.first);

  // A pointer that cannot be set is the sweep file's mistake: found here,
  // before any member runs, not as a refused row per member.
  for (std::size_t k = 0; k < sweep.members.size(); ++k) {
    try {
      (void)MemberScene(sweep, k);
    } catch (const InputError& error) {
      throw InputError(std::string("sweep: ") + error.what());
    }
  }

  sweep.out_dir = "out/sweep";
  if (file.contains("output")) {
    const json& output = file["output"];
    if (!output.is_object())
      throw InputError("sweep.output: expected an object, got " + Describe(output));
    for (const auto& [key, value] : output.items()) {
      if (key == "dir" && value.is_string() && !value.get<std::string>().empty())
        sweep.out_dir = value.get<std::string>();
      else if (key == "trajectories" && value.is_boolean())
        sweep.trajectories = value.get<bool>();
      else if (key == "dir" || key == "trajectories")
        throw InputError("sweep.output." + key + ": expected " +
                         (key == "dir" ? "a folder name" : "true or false") + ", got " +
                         Describe(value));
      else
        throw InputError("sweep.output." + key + ": unknown field (expected dir, trajectories)");
    }
  }
  return sweep;
}

json MemberScene(const Sweep& sweep, std::size_t member) {
  json scene = sweep.base;
  for (const auto& [pointer, value] : sweep.members.at(member))
    Apply(scene, pointer, value, "member " + std::to_string(member) + ": " + pointer);
  return scene;
}

}  // namespace dvi::dvisim
