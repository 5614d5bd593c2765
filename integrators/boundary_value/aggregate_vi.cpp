// SPDX-License-Identifier: Apache-2.0
#include "aggregate_vi.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <tuple>
#include <utility>

#include "check.hpp"

namespace dvi::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The variable entries in canonical order: first the dense (n + m) × (2n + m)
// block of a nonlinear step's Jacobian (row-major), then three per
// component of each ball: (u_l, u_l), (u_l, μ_B), (μ_B, u_l).
std::vector<std::pair<int, int>> VariableEntries(int n, const LiftedSet& set, bool nonlinear) {
  std::vector<std::pair<int, int>> entries;
  const int m = set.m;
  if (nonlinear)
    for (int row = 0; row < n + m; ++row)
      for (int col = 0; col < 2 * n + m; ++col) entries.emplace_back(row, col);
  for (int b = 0; b < set.r; ++b) {
    const BallBlock& ball = set.balls[static_cast<std::size_t>(b)];
    const int mu = m + set.p + b;
    for (int l = ball.offset; l < ball.offset + ball.size; ++l) {
      entries.emplace_back(n + l, 2 * n + l);
      entries.emplace_back(n + l, 2 * n + mu);
      entries.emplace_back(n + mu, 2 * n + l);
    }
  }
  return entries;
}

}  // namespace

StepTemplate BuildTemplate(const AggregateProblem& problem, double h) {
  const int n = problem.n;
  const LiftedSet& set = problem.set;
  const int m = set.m, k = set.size();
  std::vector<Eigen::Triplet<double>> entries;
  StepTemplate step;
  step.offset = Eigen::VectorXd::Zero(n + k);
  if (const AffineStep* affine = problem.affine.get()) {
    // x^{i+1} − x^i − h[p + A(θ∘x^i + (1−θ)∘x^{i+1}) + B u^{i+1}]  (9.14)
    for (int j = 0; j < n; ++j) {
      entries.emplace_back(j, j, -1.0);
      entries.emplace_back(j, n + j, 1.0);
    }
    for (Eigen::Index col = 0; col < affine->A.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(affine->A, col); it; ++it) {
        const int row = static_cast<int>(it.row()), l = static_cast<int>(col);
        const double weight = affine->theta(l);
        if (weight != 0) entries.emplace_back(row, l, -h * weight * it.value());
        if (weight != 1) entries.emplace_back(row, n + l, -h * (1 - weight) * it.value());
      }
    for (Eigen::Index col = 0; col < affine->B.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(affine->B, col); it; ++it)
        entries.emplace_back(static_cast<int>(it.row()), 2 * n + static_cast<int>(col),
                             -h * it.value());
    step.offset.head(n) = -h * affine->p;
    // w = q + C(η∘x^i + (1−η)∘x^{i+1}) + D u^{i+1}
    for (Eigen::Index col = 0; col < affine->C.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(affine->C, col); it; ++it) {
        const int row = n + static_cast<int>(it.row()), l = static_cast<int>(col);
        const double weight = affine->eta(l);
        if (weight != 0) entries.emplace_back(row, l, weight * it.value());
        if (weight != 1) entries.emplace_back(row, n + l, (1 - weight) * it.value());
      }
    for (Eigen::Index col = 0; col < affine->D.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(affine->D, col); it; ++it)
        entries.emplace_back(n + static_cast<int>(it.row()), 2 * n + static_cast<int>(col),
                             it.value());
    step.offset.segment(n, m) = affine->q;
  }
  // K's lifting: Gᵀμ_G + Eᵀν in the u-rows, h − G u and e − E u in theirs.
  const int mu_g = m, nu = m + set.p + set.r;
  for (int a = 0; a < set.p; ++a)
    for (int j = 0; j < m; ++j) {
      if (set.G(a, j) == 0) continue;
      entries.emplace_back(n + j, 2 * n + mu_g + a, set.G(a, j));
      entries.emplace_back(n + mu_g + a, 2 * n + j, -set.G(a, j));
    }
  for (int c = 0; c < set.q; ++c)
    for (int j = 0; j < m; ++j) {
      if (set.E(c, j) == 0) continue;
      entries.emplace_back(n + j, 2 * n + nu + c, set.E(c, j));
      entries.emplace_back(n + nu + c, 2 * n + j, -set.E(c, j));
    }
  step.offset.segment(n + mu_g, set.p) = set.h;
  step.offset.segment(n + nu, set.q) = set.e;

  // Every ũ-row's diagonal, explicit where zero (D = 0, a multiplier's
  // row), so that Newton's matrix diag(Da) + diag(Db) J has J's pattern.
  for (int l = 0; l < k; ++l) entries.emplace_back(n + l, 2 * n + l, 0.0);
  const std::vector<std::pair<int, int>> variable =
      VariableEntries(n, set, problem.equations != nullptr);
  for (const auto& [row, col] : variable) entries.emplace_back(row, col, 0.0);
  step.matrix.resize(n + k, 2 * n + k);
  step.matrix.setFromTriplets(entries.begin(), entries.end());
  step.matrix.makeCompressed();
  const int* outer = step.matrix.outerIndexPtr();
  const int* inner = step.matrix.innerIndexPtr();
  for (const auto& [row, col] : variable)
    step.variable.push_back(
        static_cast<int>(std::lower_bound(inner + outer[col], inner + outer[col + 1], row) - inner));
  return step;
}

namespace {

// Everything F and its Jacobian need, shared by both closures (std::function
// copies its callables).
struct AggregateData {
  BoundaryValueLayout layout;
  double h = 0;
  StepRows rows;
  LiftedSet set;
  std::shared_ptr<const SparseMatrix> matrix;
  std::shared_ptr<const Eigen::VectorXd> offset;
  std::shared_ptr<StepEquations> equations;
  int variables_per_step = 0;
  int dense_variables = 0;   // the nonlinear block's share of them
  std::vector<int> slots;    // [step · variables_per_step + v] → position in the values
  Eigen::VectorXd buffer;    // one step's (ρ, w)
  Eigen::MatrixXd jacobian;  // one step's Jacobian

  void Evaluate(const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    w.noalias() = *matrix * z;
    w += *offset;
    const int n = layout.n, m = layout.m;
    for (long s = 0; s < layout.steps; ++s) {
      if (equations) {
        equations->Evaluate(s * h, h, z.segment(layout.State(s, 0), n),
                            z.segment(layout.State(s + 1, 0), n),
                            z.segment(layout.Multiplier(s + 1, 0), m), buffer);
        for (int j = 0; j < n; ++j) w(rows.Row(s, j)) += buffer(j);
        w.segment(layout.Multiplier(s + 1, 0), m) += buffer.tail(m);
      }
      for (int b = 0; b < set.r; ++b) {
        const BallBlock& ball = set.balls[static_cast<std::size_t>(b)];
        const long u0 = layout.Multiplier(s + 1, ball.offset);
        const long mu = layout.Multiplier(s + 1, m + set.p + b);
        const Eigen::VectorXd d = z.segment(u0, ball.size) - ball.center;
        w.segment(u0, ball.size) += z(mu) * d;
        w(mu) += 0.5 * (ball.radius * ball.radius - d.squaredNorm());
      }
    }
  }

  void EvaluateJacobian(const Eigen::VectorXd& z, SparseMatrix& J) {
    J = *matrix;
    double* values = J.valuePtr();
    const int n = layout.n, m = layout.m;
    for (long s = 0; s < layout.steps; ++s) {
      const int* slot = slots.data() + s * variables_per_step;
      if (equations) {
        equations->Jacobian(s * h, h, z.segment(layout.State(s, 0), n),
                            z.segment(layout.State(s + 1, 0), n),
                            z.segment(layout.Multiplier(s + 1, 0), m), jacobian);
        const int cols = 2 * n + m;
        for (int v = 0; v < dense_variables; ++v) values[slot[v]] += jacobian(v / cols, v % cols);
      }
      int v = dense_variables;
      for (int b = 0; b < set.r; ++b) {
        const BallBlock& ball = set.balls[static_cast<std::size_t>(b)];
        const long u0 = layout.Multiplier(s + 1, ball.offset);
        const double mu = z(layout.Multiplier(s + 1, m + set.p + b));
        for (int l = 0; l < ball.size; ++l, v += 3) {
          const double d = z(u0 + l) - ball.center(l);
          values[slot[v]] += mu;
          values[slot[v + 1]] += d;
          values[slot[v + 2]] -= d;
        }
      }
    }
  }
};

}  // namespace

LiftedSet LiftSet(const ConvexSet& K) {
  LiftedSet set;
  set.m = K.dim();
  if (K.IsBox()) {
    std::tie(set.lower, set.upper) = K.BoxBounds();
    return set;
  }
  Decomposition parts = Decompose(K);
  SplitPolyhedron split = Split(parts.rows, set.m);
  DVI_THROW_UNLESS(split.empty_reason.empty(),
                   "K is empty: " << split.empty_reason.substr(0, split.empty_reason.size() - 2));
  for (const BallBlock& point : parts.points) {
    split.lower.segment(point.offset, point.size) = point.center;
    split.upper.segment(point.offset, point.size) = point.center;
  }
  set.p = static_cast<int>(split.G.rows());
  set.r = static_cast<int>(parts.balls.size());
  set.q = static_cast<int>(split.E.rows());
  set.lower.resize(set.size());
  set.upper.resize(set.size());
  set.lower << split.lower, Eigen::VectorXd::Zero(set.p + set.r), Eigen::VectorXd::Constant(set.q, -kInf);
  set.upper << split.upper, Eigen::VectorXd::Constant(set.p + set.r + set.q, kInf);
  set.G = std::move(split.G);
  set.h = std::move(split.h);
  set.E = std::move(split.E);
  set.e = std::move(split.e);
  set.balls = std::move(parts.balls);
  return set;
}

RowPlacement PlaceBoundaryRows(const BoundaryConditions& conditions) {
  const int n = static_cast<int>(conditions.M.rows());
  struct Edge {
    double weight;
    int row, component;
    bool backward;
  };
  std::vector<Edge> edges;
  for (int r = 0; r < n; ++r)
    for (int j = 0; j < n; ++j) {
      const double forward = std::abs(conditions.M(r, j)), backward = std::abs(conditions.N(r, j));
      if (forward > 0 || backward > 0)
        edges.push_back({std::max(forward, backward), r, j, backward > forward});
    }
  std::stable_sort(edges.begin(), edges.end(),
                   [](const Edge& a, const Edge& b) { return a.weight > b.weight; });
  std::vector<int> row_of(static_cast<std::size_t>(n), -1);  // per component
  std::vector<int> edge_of_row(static_cast<std::size_t>(n), -1);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const Edge& edge = edges[e];
    if (edge_of_row[static_cast<std::size_t>(edge.row)] >= 0 ||
        row_of[static_cast<std::size_t>(edge.component)] >= 0)
      continue;
    edge_of_row[static_cast<std::size_t>(edge.row)] = static_cast<int>(e);
    row_of[static_cast<std::size_t>(edge.component)] = edge.row;
  }
  // Kuhn's augmenting paths for the rows the greedy pass left unmatched.
  std::vector<char> visited;
  std::function<bool(int)> augment = [&](int row) {
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const Edge& edge = edges[e];
      const std::size_t j = static_cast<std::size_t>(edge.component);
      if (edge.row != row || visited[j]) continue;
      visited[j] = 1;
      if (row_of[j] < 0 || augment(row_of[j])) {
        row_of[j] = row;
        edge_of_row[static_cast<std::size_t>(row)] = static_cast<int>(e);
        return true;
      }
    }
    return false;
  };
  for (int r = 0; r < n; ++r) {
    if (edge_of_row[static_cast<std::size_t>(r)] >= 0) continue;
    visited.assign(static_cast<std::size_t>(n), 0);
    augment(r);
  }
  RowPlacement placement;
  placement.backward.assign(static_cast<std::size_t>(n), 0);
  placement.component_of_row.assign(static_cast<std::size_t>(n), -1);
  for (int r = 0; r < n; ++r) {
    const int e = edge_of_row[static_cast<std::size_t>(r)];
    if (e < 0) continue;
    const Edge& edge = edges[static_cast<std::size_t>(e)];
    placement.component_of_row[static_cast<std::size_t>(r)] = edge.component;
    placement.backward[static_cast<std::size_t>(edge.component)] = edge.backward;
  }
  // Rows without a matching entry (e.g. two conditions on x1, none on x2)
  // take the components left over, forward: a zero on the diagonal that
  // KLU's partial pivoting steps around.
  int free_component = 0;
  for (int r = 0; r < n; ++r) {
    if (placement.component_of_row[static_cast<std::size_t>(r)] >= 0) continue;
    while (row_of[static_cast<std::size_t>(free_component)] >= 0) ++free_component;
    row_of[static_cast<std::size_t>(free_component)] = r;
    placement.component_of_row[static_cast<std::size_t>(r)] = free_component;
  }
  return placement;
}

BoundaryConditions EquilibrateRows(const BoundaryConditions& conditions) {
  BoundaryConditions scaled = conditions;
  for (Eigen::Index r = 0; r < conditions.M.rows(); ++r) {
    const double scale = std::max(conditions.M.row(r).cwiseAbs().maxCoeff(),
                                  conditions.N.row(r).cwiseAbs().maxCoeff());
    if (scale == 0) continue;  // Validate refuses such a row (rank [M N] < n)
    scaled.M.row(r) /= scale;
    scaled.N.row(r) /= scale;
    scaled.b(r) /= scale;
    DVI_THROW_UNLESS(std::isfinite(scaled.b(r)),
                     "boundary.b[" << r << "] = " << conditions.b(r)
                                   << " is too large for its row of [M N], whose largest entry is "
                                   << scale << ": the condition overflows");
  }
  return scaled;
}

void SetBounds(const BoundaryValueLayout& layout, const LiftedSet& set, BoxMcp& mcp) {
  const long size = layout.size();
  mcp.lower.resize(size);
  mcp.upper.resize(size);
  for (long i = 0; i <= layout.steps; ++i) {
    mcp.lower.segment(layout.State(i, 0), layout.n).setConstant(-kInf);
    mcp.upper.segment(layout.State(i, 0), layout.n).setConstant(kInf);
    if (i == 0) continue;
    mcp.lower.segment(layout.Multiplier(i, 0), layout.block) = set.lower;
    mcp.upper.segment(layout.Multiplier(i, 0), layout.block) = set.upper;
  }
}

BoundaryValueMcp Assemble(const AggregateProblem& problem, long steps) {
  DVI_THROW_UNLESS(steps >= 1, "steps: " << steps << " must be at least 1");
  DVI_THROW_UNLESS(std::isfinite(problem.horizon) && problem.horizon > 0,
                   "horizon: " << problem.horizon << " is not a positive final time");
  const int n = problem.n;
  const LiftedSet& set = problem.set;
  const int k = set.size();
  auto data = std::make_shared<AggregateData>();
  data->layout = {n, set.m, k, steps};
  data->h = problem.horizon / static_cast<double>(steps);
  data->rows = {data->layout, PlaceBoundaryRows(problem.conditions)};
  data->set = set;
  data->equations = problem.equations;
  const BoundaryValueLayout& layout = data->layout;
  const long size = layout.size();
  DVI_THROW_UNLESS(size < std::numeric_limits<int>::max() / 4,
                   "steps: " << steps << " steps make " << size
                             << " unknowns, beyond KLU's 32-bit indices");

  const StepTemplate step = BuildTemplate(problem, data->h);
  const int variables = static_cast<int>(step.variable.size());
  data->variables_per_step = variables;
  data->dense_variables = problem.equations ? (n + set.m) * (2 * n + set.m) : 0;
  data->slots.assign(static_cast<std::size_t>(steps) * static_cast<std::size_t>(variables), -1);
  std::vector<int> variable_of_slot(static_cast<std::size_t>(step.matrix.nonZeros()), -1);
  for (int v = 0; v < variables; ++v)
    variable_of_slot[static_cast<std::size_t>(step.variable[static_cast<std::size_t>(v)])] = v;

  const StepRows& rows = data->rows;

  // Compressed columns by blocks of columns (ũ^i, x^i), block 0 being x^0:
  // a column's entries come from the steps that see it (as x^i, as x^{i+1}
  // or as ũ^{i+1}) and from the boundary rows, sorted by row. Blocks 2 to
  // steps − 1 touch neither x^0 nor the boundary rows, and each is block 2
  // shifted by (i − 2)(k + n) rows: block 2 is built entry by entry, the
  // others are copies of it (the sorting took 0.5 s of a 4 s solve at 10⁶
  // steps when every column was built so).
  const Eigen::MatrixXd& M = problem.conditions.M;
  const Eigen::MatrixXd& N = problem.conditions.N;
  struct Entry {
    long row;
    double value;
    long tag;  // step · variables + v, or −1
  };
  struct Chunk {
    std::vector<int> counts;  // entries per column
    std::vector<Entry> entries;
  };
  const int* t_outer = step.matrix.outerIndexPtr();
  const int* t_inner = step.matrix.innerIndexPtr();
  const double* t_values = step.matrix.valuePtr();
  const auto gather_block = [&](long i, Chunk& chunk) {
    chunk.counts.clear();
    chunk.entries.clear();
    std::size_t begin = 0;
    const auto add_local = [&](long s, int local_col) {
      for (int slot = t_outer[local_col]; slot < t_outer[local_col + 1]; ++slot) {
        const int v = variable_of_slot[static_cast<std::size_t>(slot)];
        chunk.entries.push_back(
            {rows.Row(s, t_inner[slot]), t_values[slot], v < 0 ? -1 : s * variables + v});
      }
    };
    const auto close_column = [&] {
      std::sort(chunk.entries.begin() + static_cast<std::ptrdiff_t>(begin), chunk.entries.end(),
                [](const Entry& a, const Entry& b) { return a.row < b.row; });
      chunk.counts.push_back(static_cast<int>(chunk.entries.size() - begin));
      begin = chunk.entries.size();
    };
    if (i > 0)
      for (int l = 0; l < k; ++l) {
        add_local(i - 1, 2 * n + l);
        close_column();
      }
    for (int j = 0; j < n; ++j) {
      if (i >= 1) add_local(i - 1, n + j);
      if (i < steps) add_local(i, j);
      // The boundary row placed on this column's diagonal keeps its entry
      // there even when zero (a row matched to another component).
      const Eigen::MatrixXd* conditions = i == 0 ? &M : (i == steps ? &N : nullptr);
      if (conditions)
        for (int r = 0; r < n; ++r)
          if ((*conditions)(r, j) != 0 || rows.BoundaryRow(r) == layout.State(i, j))
            chunk.entries.push_back({rows.BoundaryRow(r), (*conditions)(r, j), -1});
      close_column();
    }
  };
  constexpr long kTemplateBlock = 2;
  const bool stamped = steps > kTemplateBlock + 1;
  Chunk first, second, interior, last;
  gather_block(0, first);
  if (stamped) {
    gather_block(1, second);
    gather_block(kTemplateBlock, interior);
    gather_block(steps, last);
  }
  std::size_t nonzeros = 0;
  if (stamped) {
    nonzeros = first.entries.size() + second.entries.size() + last.entries.size() +
               static_cast<std::size_t>(steps - kTemplateBlock) * interior.entries.size();
  } else {
    Chunk chunk;
    for (long i = 1; i <= steps; ++i) {
      gather_block(i, chunk);
      nonzeros += chunk.entries.size();
    }
    nonzeros += first.entries.size();
  }
  auto matrix = std::make_shared<SparseMatrix>(size, size);
  matrix->resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  int* outer = matrix->outerIndexPtr();
  int* inner = matrix->innerIndexPtr();
  double* values = matrix->valuePtr();
  long column = 0;
  int position = 0;
  const auto write = [&](const Chunk& chunk, long row_shift, long tag_shift) {
    std::size_t e = 0;
    for (const int count : chunk.counts) {
      outer[column++] = position;
      for (int c = 0; c < count; ++c, ++e) {
        const Entry& entry = chunk.entries[e];
        if (entry.tag >= 0)
          data->slots[static_cast<std::size_t>(entry.tag + tag_shift)] = position;
        inner[position] = static_cast<int>(entry.row + row_shift);
        values[position] = entry.value;
        ++position;
      }
    }
  };
  write(first, 0, 0);
  if (stamped) {
    write(second, 0, 0);
    for (long i = kTemplateBlock; i < steps; ++i)
      write(interior, (i - kTemplateBlock) * (k + n), (i - kTemplateBlock) * variables);
    write(last, 0, 0);
  } else {
    Chunk chunk;
    for (long i = 1; i <= steps; ++i) {
      gather_block(i, chunk);
      write(chunk, 0, 0);
    }
  }
  outer[column] = position;
  data->matrix = matrix;

  auto offset = std::make_shared<Eigen::VectorXd>(Eigen::VectorXd::Zero(size));
  for (long s = 0; s < steps; ++s)
    for (int row = 0; row < n + k; ++row) (*offset)(rows.Row(s, row)) += step.offset(row);
  for (int r = 0; r < n; ++r) (*offset)(rows.BoundaryRow(r)) -= problem.conditions.b(r);
  data->offset = offset;
  data->buffer.resize(n + set.m);
  data->jacobian.resize(n + set.m, 2 * n + set.m);

  BoundaryValueMcp out;
  out.layout = layout;
  out.horizon = problem.horizon;
  out.h = data->h;
  out.matrix = matrix;
  out.offset = data->offset;
  out.affine = variables == 0;
  SetBounds(layout, set, out.mcp);
  out.mcp.F = [data](const Eigen::VectorXd& z, Eigen::VectorXd& w) { data->Evaluate(z, w); };
  out.mcp.sparse_jacobian = [data](const Eigen::VectorXd& z, SparseMatrix& J) {
    data->EvaluateJacobian(z, J);
  };
  if (out.affine) out.mcp.constant_jacobian = matrix;
  return out;
}

}  // namespace dvi::internal
