// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dvi/error.hpp"
#include "dvi/trajectory.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {

/// The small steps every scene reader takes (scene_file.cpp, and the
/// boundary-value and game readers of boundary_scene.cpp): fields named by
/// their JSON path, unknown fields refused.

/// @throws InputError "path: message".
[[noreturn]] void Fail(const std::string& path, const std::string& message);
/// "path.key" ("key" at the top level).
std::string Field(const std::string& path, const std::string& key);
/// "path[k]".
std::string Indexed(const std::string& path, std::size_t k);
/// object[key], or nullptr when absent.
const nlohmann::json* FindField(const nlohmann::json& object, const std::string& key);
/// @throws InputError naming the first field of object not in `known`
/// (context, e.g. " for type lcs", follows its name).
void RejectUnknownFields(const nlohmann::json& object, const std::string& path,
                         const std::vector<std::string>& known, const std::string& context = "");
/// @throws InputError unless value is an object.
void RequireObject(const nlohmann::json& value, const std::string& path);

/// The method named `name` ("auto", "stepping", "event" or "bvp": the
/// ToString of the scene's IntegrationMethod values). @throws InputError
/// "path: unknown method ... (expected auto, stepping, event or bvp)".
IntegrationMethod ReadSceneMethod(const std::string& name, const std::string& path);

/// A number in [0, 1]. @throws InputError naming path otherwise.
double ReadUnitInterval(const nlohmann::json& value, const std::string& path);
/// A number > 0. @throws InputError naming path otherwise.
double ReadPositive(const nlohmann::json& value, const std::string& path);
/// An integer ≥ 1. @throws InputError naming path otherwise.
long ReadCount(const nlohmann::json& value, const std::string& path);
/// @throws InputError "path: is RxC, expected rows x cols" on another shape.
void CheckShape(const MatrixField& M, const std::string& path, Eigen::Index rows,
                Eigen::Index cols);
/// The matrix as sparse (column-major), dense input converted.
SparseMatrix ToSparse(const MatrixField& M);

/// Library constructors and Validate() check their arguments; their messages
/// gain the JSON path so the user knows which field to fix.
template <typename Build>
auto WithPath(const std::string& path, Build build) -> decltype(build()) {
  try {
    return build();
  } catch (const InvalidInputError& error) {
    Fail(path, error.what());
  }
}

}  // namespace dvi::dvisim
