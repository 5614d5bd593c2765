// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "dvi/complementarity_problem.hpp"

namespace dvi::dvisim {

/// Reading numbers, vectors and matrices from dvisim's JSON files
/// (/work/shared/docs/scene-format.md conventions): vectors are arrays,
/// matrices row-major nested arrays or {"sparse": {"rows", "cols", "i", "j",
/// "v"}} zero-based triplets (duplicates summed), and a number may be written
/// as the string "inf" or "-inf" where infinite values make sense.
///
/// Every reader takes the JSON path of the value ("problem.M") and reports
/// bad input as InputError with a one-line message that starts with that path
/// and the index ("problem.q[1]: expected a number, got \"abc\"").

/// A mistake in an input file; what() is the one-line message for the user.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The whole text of the file at path. @throws InputError "PATH: cannot
/// open (reason)" or "PATH: cannot read the file".
std::string ReadTextFile(const std::string& path);

/// parse(ReadTextFile(path)), an InputError from parsing prefixed with the
/// path ("scene.json: x0: ...").
template <typename Parse>
auto ParseFile(const std::string& path, Parse parse) -> decltype(parse(std::string()));

/// Parses JSON text. @throws InputError "malformed JSON at line L, column C: ...".
nlohmann::json ParseJson(const std::string& text);

/// A short rendering of a JSON value for messages: strings quoted, long
/// values cut off.
std::string Describe(const nlohmann::json& value);

/// object[key]. @throws InputError "PATH: missing field \"key\"" when absent,
/// or "PATH: expected an object, got ..." when object is not one.
const nlohmann::json& RequireField(const nlohmann::json& object, const std::string& key,
                                   const std::string& path);

/// A number, or "inf" / "-inf" when allow_infinite.
/// @throws InputError naming path and what was found.
double ReadNumber(const nlohmann::json& value, const std::string& path, bool allow_infinite);

/// An integer in [0, bound). @throws InputError otherwise.
int ReadIndex(const nlohmann::json& value, const std::string& path, int bound);

/// An array of numbers. expected_size < 0 accepts any length.
/// @throws InputError on a non-array, a wrong length, or a bad entry.
Eigen::VectorXd ReadVector(const nlohmann::json& value, const std::string& path,
                           bool allow_infinite, int expected_size = -1);

/// A matrix as written in the file, dense or sparse. Entries are finite.
struct MatrixField {
  bool is_sparse = false;
  Eigen::MatrixXd dense;  ///< When !is_sparse.
  SparseMatrix sparse;    ///< When is_sparse.
  Eigen::Index rows() const { return is_sparse ? sparse.rows() : dense.rows(); }
  Eigen::Index cols() const { return is_sparse ? sparse.cols() : dense.cols(); }
  Eigen::MatrixXd ToDense() const { return is_sparse ? Eigen::MatrixXd(sparse) : dense; }
};

/// A row-major nested array (every row the same length; [] is 0×0) or a
/// {"sparse": ...} object. @throws InputError naming the row or entry.
MatrixField ReadMatrix(const nlohmann::json& value, const std::string& path);

/// A JSON number, or "inf" / "-inf" / "nan" for non-finite values (JSON has
/// no literal for them; the strings follow the input convention).
nlohmann::ordered_json NumberToJson(double value);
nlohmann::ordered_json VectorToJson(const Eigen::VectorXd& v);

template <typename Parse>
auto ParseFile(const std::string& path, Parse parse) -> decltype(parse(std::string())) {
  const std::string text = ReadTextFile(path);
  try {
    return parse(text);
  } catch (const InputError& error) {
    throw InputError(path + ": " + error.what());
  }
}

}  // namespace dvi::dvisim
