// SPDX-License-Identifier: Apache-2.0
#include "json_reading.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

namespace dvi::dvisim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Messages quote at most this many characters of an offending value.
constexpr std::size_t kMaxQuoted = 40;
// Matrices and vectors larger than this are a corrupt or mistaken file, not a
// problem dvisim should try to allocate.
constexpr std::int64_t kMaxEntries = std::int64_t{1} << 28;
// The largest dimension of a sparse matrix (10⁷: circuits of 10⁵ nodes are
// the largest the project measures).
constexpr int kMaxSparseDimension = 10'000'000;

// Deeper nesting than any scene needs; nlohmann's recursive parser would
// exhaust the stack somewhere beyond 10⁴ levels.
constexpr int kMaxJsonDepth = 256;

// Line and column (1-based) of text[offset].
std::string Position(const std::string& text, std::size_t offset) {
  std::size_t line = 1;
  std::size_t column = 1;
  for (std::size_t k = 0; k < std::min(offset, text.size()); ++k) {
    if (text[k] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Refuses nesting deeper than kMaxJsonDepth before the parser recurses into it.
void CheckDepth(const std::string& text) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (in_string) {
      if (c == '\\') ++k;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError("malformed JSON at " + Position(text, k) + ": nested deeper than " +
                         std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

std::string Indexed(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// Refuses a key given twice in one object, which nlohmann would silently
// resolve to one of the two values. Tracks the path of the value being
// parsed, so the message names it as the readers do ("method.h").
class DuplicateKeyCheck {
 public:
  bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start: frames_.push_back({true, {}, "", 0}); break;
      case Event::array_start: frames_.push_back({false, {}, "", 0}); break;
      case Event::key: {
        Frame& object = frames_.back();
        object.key = parsed.get<std::string>();
        if (!object.keys.insert(object.key).second)
          throw InputError(Path() + ": duplicate key \"" + object.key +
                           "\" in one object (JSON leaves its value undefined)");
        break;
      }
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        [[fallthrough]];
      case Event::value:
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;    // of an object: the key being read
    std::size_t index;  // of an array: the element being read
  };

  std::string Path() const {
    std::string path;
    for (const Frame& frame : frames_)
      path = frame.object ? (path.empty() ? frame.key : path + "." + frame.key)
                          : Indexed(path, frame.index);
    return path;
  }

  std::vector<Frame> frames_;
};

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

}  // namespace

nlohmann::json ParseJson(const std::string& text) {
  CheckDepth(text);
  try {
    return nlohmann::json::parse(text, DuplicateKeyCheck());
  } catch (const nlohmann::json::parse_error& error) {
    // error.byte is the 1-based offset of the character that broke parsing.
    const std::size_t end = std::min<std::size_t>(error.byte == 0 ? 0 : error.byte - 1, text.size());
    // nlohmann's what() is "[json.exception.parse_error.101] parse error at
    // line L, column C: DETAIL"; keep DETAIL.
    std::string detail = error.what();
    const std::size_t column_word = detail.find("column ");
    const std::size_t colon = detail.find(": ", column_word == std::string::npos ? 0 : column_word);
    if (colon != std::string::npos) detail = detail.substr(colon + 2);
    throw InputError("malformed JSON at " + Position(text, end) + ": " + detail);
  } catch (const nlohmann::json::out_of_range& error) {
    // "[json.exception.out_of_range.406] number overflow parsing '4e400'".
    std::string detail = error.what();
    const std::size_t bracket = detail.find("] ");
    if (bracket != std::string::npos) detail = detail.substr(bracket + 2);
    throw InputError("malformed JSON: " + detail + " (beyond double precision, about 1.8e308)");
  }
}

std::string Describe(const nlohmann::json& value) {
  std::string text = value.dump();
  if (text.size() > kMaxQuoted) text = text.substr(0, kMaxQuoted) + "...";
  return text;
}

const nlohmann::json& RequireField(const nlohmann::json& object, const std::string& key,
                                   const std::string& path) {
  if (!object.is_object()) Fail(path, "expected an object, got " + Describe(object));
  const auto it = object.find(key);
  if (it == object.end()) Fail(path, "missing field \"" + key + "\"");
  return *it;
}

double ReadNumber(const nlohmann::json& value, const std::string& path, bool allow_infinite) {
  if (value.is_number()) return value.get<double>();
  if (value.is_string() && allow_infinite) {
    const std::string& word = value.get_ref<const std::string&>();
    if (word == "inf" || word == "+inf") return kInf;
    if (word == "-inf") return -kInf;
  }
  if (value.is_string() && (value == "inf" || value == "+inf" || value == "-inf"))
    Fail(path, "expected a finite number, got " + Describe(value));
  Fail(path, std::string(allow_infinite ? "expected a number or \"inf\"/\"-inf\"" : "expected a number") +
                 ", got " + Describe(value));
}

int ReadIndex(const nlohmann::json& value, const std::string& path, int bound) {
  if (value.is_number_integer()) {
    const std::int64_t index = value.get<std::int64_t>();
    if (index >= 0 && index < bound) return static_cast<int>(index);
  }
  Fail(path, "expected an integer in [0, " + std::to_string(bound) + "), got " + Describe(value));
}

Eigen::VectorXd ReadVector(const nlohmann::json& value, const std::string& path,
                           bool allow_infinite, int expected_size) {
  if (!value.is_array()) Fail(path, "expected an array of numbers, got " + Describe(value));
  if (static_cast<std::int64_t>(value.size()) > kMaxEntries)
    Fail(path, "has " + std::to_string(value.size()) + " entries, more than dvisim accepts");
  if (expected_size >= 0 && value.size() != static_cast<std::size_t>(expected_size))
    Fail(path, "has " + std::to_string(value.size()) + " entries, expected " +
                   std::to_string(expected_size));
  Eigen::VectorXd v(static_cast<Eigen::Index>(value.size()));
  for (std::size_t i = 0; i < value.size(); ++i)
    v(static_cast<Eigen::Index>(i)) = ReadNumber(value[i], Indexed(path, i), allow_infinite);
  return v;
}

MatrixField ReadMatrix(const nlohmann::json& value, const std::string& path) {
  MatrixField matrix;
  if (value.is_object()) {
    const std::string sparse_path = path + ".sparse";
    const nlohmann::json& sparse = RequireField(value, "sparse", path);
    if (value.size() != 1) Fail(path, "a sparse matrix is {\"sparse\": {...}} and nothing else");
    for (const auto& item : sparse.items())
      if (item.key() != "rows" && item.key() != "cols" && item.key() != "i" && item.key() != "j" &&
          item.key() != "v")
        Fail(sparse_path, "unknown field \"" + item.key() + "\" (expected rows, cols, i, j, v)");
    // Eigen allocates a column's pointer per column, whatever the entries:
    // a dimension beyond any circuit is a mistaken file, refused before that.
    const int rows = ReadIndex(RequireField(sparse, "rows", sparse_path), sparse_path + ".rows",
                               kMaxSparseDimension + 1);
    const int cols = ReadIndex(RequireField(sparse, "cols", sparse_path), sparse_path + ".cols",
                               kMaxSparseDimension + 1);
    const nlohmann::json& i = RequireField(sparse, "i", sparse_path);
    const nlohmann::json& j = RequireField(sparse, "j", sparse_path);
    const Eigen::VectorXd v = ReadVector(RequireField(sparse, "v", sparse_path), sparse_path + ".v",
                                         /*allow_infinite=*/false);
    for (const auto& [name, indices] : {std::pair{"i", &i}, std::pair{"j", &j}})
      if (!indices->is_array() || indices->size() != static_cast<std::size_t>(v.size()))
        Fail(sparse_path + "." + name, "expected an array of " + std::to_string(v.size()) +
                                           " indices (as many as v), got " + Describe(*indices));
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(v.size()));
    for (std::size_t k = 0; k < static_cast<std::size_t>(v.size()); ++k)
      triplets.emplace_back(ReadIndex(i[k], Indexed(sparse_path + ".i", k), rows),
                            ReadIndex(j[k], Indexed(sparse_path + ".j", k), cols),
                            v(static_cast<Eigen::Index>(k)));
    matrix.is_sparse = true;
    matrix.sparse.resize(rows, cols);
    matrix.sparse.setFromTriplets(triplets.begin(), triplets.end());  // Sums duplicates.
    return matrix;
  }
  if (!value.is_array())
    Fail(path, "expected an array of rows or {\"sparse\": {...}}, got " + Describe(value));
  const std::size_t rows = value.size();
  std::size_t cols = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    if (!value[r].is_array()) Fail(Indexed(path, r), "expected an array (a row), got " + Describe(value[r]));
    if (r == 0) cols = value[0].size();
    if (value[r].size() != cols)
      Fail(path, "row " + std::to_string(r) + " has " + std::to_string(value[r].size()) +
                     " entries, expected " + std::to_string(cols));
  }
  if (static_cast<std::int64_t>(rows) * static_cast<std::int64_t>(cols) > kMaxEntries)
    Fail(path, "is too large");
  matrix.dense.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
      matrix.dense(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
          ReadNumber(value[r][c], Indexed(Indexed(path, r), c), /*allow_infinite=*/false);
  return matrix;
}

nlohmann::ordered_json NumberToJson(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return value;
}

nlohmann::ordered_json VectorToJson(const Eigen::VectorXd& v) {
  nlohmann::ordered_json array = nlohmann::ordered_json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) array.push_back(NumberToJson(v(i)));
  return array;
}

std::string ReadTextFile(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    throw InputError(path + ": is a directory, not a JSON file");
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::ostringstream contents;
  contents << stream.rdbuf();
  if (stream.bad()) throw InputError(path + ": cannot read the file");
  return contents.str();
}

}  // namespace dvi::dvisim
