// SPDX-License-Identifier: Apache-2.0
#include "problem_file.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "dvi/error.hpp"

namespace dvi::dvisim {
namespace {

using nlohmann::json;

constexpr double kInf = std::numeric_limits<double>::infinity();

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

std::string Join(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : ", ") + word;
  return text;
}

void RejectUnknownFields(const json& object, const std::string& path,
                         const std::vector<std::string>& known, const std::string& context) {
  for (const auto& item : object.items()) {
    bool found = false;
    for (const std::string& key : known) found = found || key == item.key();
    if (!found)
      Fail(path, "unknown field \"" + item.key() + "\"" + context + " (expected " + Join(known) + ")");
  }
}

const json* FindField(const json& object, const std::string& key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

std::string Field(const std::string& path, const std::string& key) { return path + "." + key; }

// Library constructors check their arguments; their messages gain the JSON
// path so the user knows which field to fix.
template <typename Build>
ConvexSet WithPath(const std::string& path, Build build) {
  try {
    return build();
  } catch (const InvalidInputError& error) {
    Fail(path, error.what());
  }
}

ConvexSet ReadBox(const json& box, const std::string& path) {
  if (!box.is_object()) Fail(path, "expected {\"lower\": [...], \"upper\": [...]}, got " + Describe(box));
  RejectUnknownFields(box, path, {"lower", "upper"}, "");
  Eigen::VectorXd lower = ReadVector(RequireField(box, "lower", path), Field(path, "lower"), true);
  Eigen::VectorXd upper = ReadVector(RequireField(box, "upper", path), Field(path, "upper"), true,
                                     static_cast<int>(lower.size()));
  for (Eigen::Index i = 0; i < lower.size(); ++i)
    if (!(lower(i) <= upper(i)) || lower(i) == kInf || upper(i) == -kInf)
      Fail(path, "lower[" + std::to_string(i) + "] = " + Describe(NumberToJson(lower(i))) +
                     " and upper[" + std::to_string(i) + "] = " + Describe(NumberToJson(upper(i))) +
                     " leave no room (need lower ≤ upper, lower < inf, upper > -inf)");
  return WithPath(path, [&] { return ConvexSet::Box(std::move(lower), std::move(upper)); });
}

Eigen::MatrixXd ReadConstraintMatrix(const json& value, const std::string& path, int& dim) {
  Eigen::MatrixXd A = ReadMatrix(value, path).ToDense();
  if (A.rows() == 0) return Eigen::MatrixXd(0, dim < 0 ? 0 : dim);
  if (dim >= 0 && A.cols() != dim)
    Fail(path, "has " + std::to_string(A.cols()) + " columns, expected " + std::to_string(dim));
  dim = static_cast<int>(A.cols());
  return A;
}

// Refuses a row of [A b] that repeats an earlier one up to a positive
// factor (any non-zero factor for equalities): the same constraint twice leaves its multipliers non-unique, and
// a projection's KKT system then degenerates (1001 copies of one constraint
// took minutes; a dense KKT solve is cubic in the rows).
void RefuseRepeatedRows(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                        const std::string& A_path, const std::string& b_name, bool equalities) {
  std::map<std::vector<double>, Eigen::Index> seen;
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    double scale = std::max(A.row(r).lpNorm<Eigen::Infinity>(), std::abs(b(r)));
    if (scale == 0) continue;  // 0 ≤ 0 or 0 = 0: ConvexSet's own checks
    if (equalities) {
      Eigen::Index lead = 0;
      while (lead < A.cols() && A(r, lead) == 0) ++lead;
      if ((lead < A.cols() ? A(r, lead) : b(r)) < 0) scale = -scale;
    }
    std::vector<double> key(static_cast<std::size_t>(A.cols()) + 1);
    for (Eigen::Index c = 0; c < A.cols(); ++c) key[static_cast<std::size_t>(c)] = A(r, c) / scale;
    key.back() = b(r) / scale;
    const auto [first, inserted] = seen.emplace(std::move(key), r);
    if (!inserted)
      Fail(A_path + "[" + std::to_string(r) + "]",
           "repeats the constraint of row " + std::to_string(first->second) + " (with " + b_name +
               (equalities ? ", up to a factor" : ", up to a positive factor") +
               "); give each constraint once");
  }
}

ConvexSet ReadPolyhedron(const json& polyhedron, const std::string& path, std::optional<int> dim) {
  if (!polyhedron.is_object())
    Fail(path, "expected {\"G\": [[...]], \"h\": [...], \"E\": [[...]], \"e\": [...]}, got " +
                   Describe(polyhedron));
  RejectUnknownFields(polyhedron, path, {"G", "h", "E", "e"}, "");
  int columns = dim ? *dim : -1;
  const json empty = json::array();
  const json* G_json = FindField(polyhedron, "G");
  const json* E_json = FindField(polyhedron, "E");
  if (!G_json && !E_json) Fail(path, "needs \"G\" and \"h\", or \"E\" and \"e\", or both");
  Eigen::MatrixXd G = ReadConstraintMatrix(G_json ? *G_json : empty, Field(path, "G"), columns);
  Eigen::MatrixXd E = ReadConstraintMatrix(E_json ? *E_json : empty, Field(path, "E"), columns);
  if (columns < 0) Fail(path, "G and E have no rows, so the dimension of the set is unknown");
  if (G.cols() != columns) G.resize(G.rows(), columns);
  if (E.cols() != columns) E.resize(E.rows(), columns);
  const json* h_json = FindField(polyhedron, "h");
  const json* e_json = FindField(polyhedron, "e");
  if (G.rows() > 0 && !h_json) Fail(path, "missing field \"h\" (G has rows)");
  if (E.rows() > 0 && !e_json) Fail(path, "missing field \"e\" (E has rows)");
  Eigen::VectorXd h = ReadVector(h_json ? *h_json : empty, Field(path, "h"), false,
                                 static_cast<int>(G.rows()));
  Eigen::VectorXd e = ReadVector(e_json ? *e_json : empty, Field(path, "e"), false,
                                 static_cast<int>(E.rows()));
  RefuseRepeatedRows(G, h, Field(path, "G"), "h", false);
  RefuseRepeatedRows(E, e, Field(path, "E"), "e", true);
  return WithPath(path, [&] {
    return ConvexSet::Polyhedron(std::move(G), std::move(h), std::move(E), std::move(e));
  });
}

ConvexSet ReadBall(const json& ball, const std::string& path) {
  if (!ball.is_object()) Fail(path, "expected {\"center\": [...], \"radius\": r}, got " + Describe(ball));
  RejectUnknownFields(ball, path, {"center", "radius"}, "");
  Eigen::VectorXd center = ReadVector(RequireField(ball, "center", path), Field(path, "center"), false);
  const double radius = ReadNumber(RequireField(ball, "radius", path), Field(path, "radius"), false);
  if (radius < 0) Fail(Field(path, "radius"), "expected a number ≥ 0, got " + Describe(radius));
  return WithPath(path, [&] { return ConvexSet::Ball(std::move(center), radius); });
}

ConvexSet ReadProduct(const json& parts, const std::string& path, std::optional<int> dim) {
  if (!parts.is_array() || parts.empty())
    Fail(path, "expected a non-empty array of sets, got " + Describe(parts));
  std::vector<std::optional<ConvexSet>> sets(parts.size());
  int known = 0;
  int orthant_part = -1;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::string part_path = path + "[" + std::to_string(k) + "]";
    if (parts[k] == "orthant") {
      if (orthant_part >= 0)
        Fail(part_path, "a second \"orthant\" part: the sizes of the two are ambiguous (give a box "
                        "with lower 0 and upper \"inf\" instead)");
      orthant_part = static_cast<int>(k);
      continue;
    }
    sets[k] = ReadSet(parts[k], part_path, std::nullopt);
    known += sets[k]->dim();
  }
  if (orthant_part >= 0) {
    const std::string part_path = path + "[" + std::to_string(orthant_part) + "]";
    if (!dim) Fail(part_path, "\"orthant\" inside a product needs the dimension of the product");
    if (*dim - known < 0)
      Fail(path, "the other parts already have dimension " + std::to_string(known) +
                     ", more than " + std::to_string(*dim));
    sets[static_cast<std::size_t>(orthant_part)] = ConvexSet::Orthant(*dim - known);
  }
  std::vector<ConvexSet> list;
  for (auto& set : sets) list.push_back(std::move(*set));
  return WithPath(path, [&] { return ConvexSet::Product(std::move(list)); });
}

void CheckSquare(const MatrixField& M, const std::string& path) {
  if (M.rows() != M.cols())
    Fail(path, "is " + std::to_string(M.rows()) + "x" + std::to_string(M.cols()) +
                   ", expected a square matrix");
}

}  // namespace

std::string ToString(ProblemType type) {
  switch (type) {
    case ProblemType::kLcp:
      return "lcp";
    case ProblemType::kMcp:
      return "mcp";
    case ProblemType::kAvi:
      return "avi";
  }
  return "unknown";
}

ConvexSet ReadSet(const json& value, const std::string& path, std::optional<int> dim) {
  ConvexSet set = ConvexSet::Orthant(0);
  if (value.is_string()) {
    if (value != "orthant")
      Fail(path, "unknown set " + Describe(value) +
                     " (expected \"orthant\", {\"box\": ...}, {\"polyhedron\": ...}, "
                     "{\"ball\": ...} or {\"product\": [...]})");
    if (!dim) Fail(path, "\"orthant\" here needs a known dimension");
    return ConvexSet::Orthant(*dim);
  }
  if (!value.is_object() || value.size() != 1)
    Fail(path, "expected \"orthant\" or an object with one of box, polyhedron, ball, product, got " +
                   Describe(value));
  const std::string kind = value.begin().key();
  const json& body = value.begin().value();
  const std::string body_path = Field(path, kind);
  if (kind == "box") {
    set = ReadBox(body, body_path);
  } else if (kind == "polyhedron") {
    set = ReadPolyhedron(body, body_path, dim);
  } else if (kind == "ball") {
    set = ReadBall(body, body_path);
  } else if (kind == "product") {
    set = ReadProduct(body, body_path, dim);
  } else {
    Fail(path, "unknown set kind \"" + kind + "\" (expected box, polyhedron, ball or product)");
  }
  if (dim && set.dim() != *dim)
    Fail(path, "has dimension " + std::to_string(set.dim()) + ", expected " + std::to_string(*dim));
  return set;
}

double ReadTolerance(const json& value, const std::string& path) {
  const double tolerance = ReadNumber(value, path, false);
  if (!(tolerance > 0.0 && tolerance < 1.0))
    Fail(path, "expected a tolerance in (0, 1), got " + Describe(value));
  return tolerance;
}

SolverMethod ReadSolver(const json& value, const std::string& path) {
  if (!value.is_string()) Fail(path, "expected a solver name, got " + Describe(value));
  try {
    return ParseSolverMethod(value.get_ref<const std::string&>());
  } catch (const InvalidInputError& error) {
    Fail(path, error.what());
  }
}

ProblemFile ParseProblemFile(const std::string& text) {
  const json root = ParseJson(text);
  if (!root.is_object()) Fail("(file)", "expected a JSON object, got " + Describe(root));
  RejectUnknownFields(root, "(file)", {"name", "description", "problem", "solver", "tol"}, "");
  ProblemFile file;
  if (const json* name = FindField(root, "name")) {
    if (!name->is_string()) Fail("name", "expected a string, got " + Describe(*name));
    file.name = name->get<std::string>();
  }
  const std::string path = "problem";
  const json& problem = RequireField(root, "problem", "(file)");
  const json& type = RequireField(problem, "type", path);
  std::vector<std::string> fields{"type", "solver", "tol", "M", "q"};
  if (type == "lcp") {
    file.type = ProblemType::kLcp;
  } else if (type == "mcp") {
    file.type = ProblemType::kMcp;
    fields.insert(fields.end(), {"lower", "upper"});
  } else if (type == "avi") {
    file.type = ProblemType::kAvi;
    fields.push_back("set");
  } else {
    Fail(Field(path, "type"), "expected \"lcp\", \"mcp\" or \"avi\", got " + Describe(type));
  }
  RejectUnknownFields(problem, path, fields, " for type " + ToString(file.type));

  file.M = ReadMatrix(RequireField(problem, "M", path), Field(path, "M"));
  CheckSquare(file.M, Field(path, "M"));
  const int m = static_cast<int>(file.M.rows());
  file.q = ReadVector(RequireField(problem, "q", path), Field(path, "q"), false, m);
  if (file.type == ProblemType::kMcp) {
    file.lower = ReadVector(RequireField(problem, "lower", path), Field(path, "lower"), true, m);
    file.upper = ReadVector(RequireField(problem, "upper", path), Field(path, "upper"), true, m);
    for (int i = 0; i < m; ++i) {
      const std::string index = "[" + std::to_string(i) + "]";
      if (file.lower(i) == kInf) Fail(Field(path, "lower") + index, "must be below \"inf\"");
      if (file.upper(i) == -kInf) Fail(Field(path, "upper") + index, "must be above \"-inf\"");
      if (file.lower(i) > file.upper(i))
        Fail(Field(path, "lower") + index,
             Describe(NumberToJson(file.lower(i))) + " is above upper" + index + " = " +
                 Describe(NumberToJson(file.upper(i))));
    }
  }
  if (file.type == ProblemType::kAvi) {
    const json* set = FindField(problem, "set");
    file.set = set ? ReadSet(*set, Field(path, "set"), m) : ConvexSet::Orthant(m);
  }

  for (const std::string key : {"solver", "tol"}) {
    if (FindField(root, key) && FindField(problem, key))
      Fail(Field(path, key), "given both here and at the top level");
  }
  const auto either = [&](const std::string& key, std::string& where) -> const json* {
    if (const json* value = FindField(root, key)) {
      where = key;
      return value;
    }
    where = Field(path, key);
    return FindField(problem, key);
  };
  std::string where;
  if (const json* solver = either("solver", where)) file.solver = ReadSolver(*solver, where);
  if (const json* tol = either("tol", where)) file.tolerance = ReadTolerance(*tol, where);
  return file;
}

ProblemFile ReadProblemFile(const std::string& path) {
  return ParseFile(path, ParseProblemFile);
}

}  // namespace dvi::dvisim
