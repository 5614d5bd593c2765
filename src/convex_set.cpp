// SPDX-License-Identifier: Apache-2.0
#include "dvi/convex_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "check.hpp"
#include "convex_set_data.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string KindName(ConvexSet::Kind kind) {
  switch (kind) {
    case ConvexSet::Kind::kOrthant:
      return "orthant";
    case ConvexSet::Kind::kBox:
      return "box";
    case ConvexSet::Kind::kPolyhedron:
      return "polyhedron";
    case ConvexSet::Kind::kBall:
      return "ball";
    case ConvexSet::Kind::kProduct:
      return "product";
  }
  return "set";
}

}  // namespace

// ---------------------------------------------------------------------------
// Factories.

ConvexSet::ConvexSet(std::shared_ptr<const Data> data) : data_(std::move(data)) {}

ConvexSet ConvexSet::Orthant(int m) {
  DVI_THROW_UNLESS(m >= 0, "Orthant dimension m = " << m << " is negative");
  auto data = std::make_shared<Data>();
  data->kind = Kind::kOrthant;
  data->dim = m;
  data->is_box = true;
  data->is_polyhedral = true;
  data->lower = Eigen::VectorXd::Zero(m);
  data->upper = Eigen::VectorXd::Constant(m, kInf);
  data->num_inequalities = m;
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Box(Eigen::VectorXd lower, Eigen::VectorXd upper) {
  DVI_THROW_UNLESS(lower.size() == upper.size(),
                   "Box: lower has " << lower.size() << " entries but upper has " << upper.size());
  int finite_bounds = 0;
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    DVI_THROW_UNLESS(!std::isnan(lower(i)), "Box: lower(" << i << ") is NaN");
    DVI_THROW_UNLESS(!std::isnan(upper(i)), "Box: upper(" << i << ") is NaN");
    DVI_THROW_UNLESS(lower(i) <= upper(i), "Box: lower(" << i << ") = " << lower(i)
                                                         << " exceeds upper(" << i
                                                         << ") = " << upper(i));
    DVI_THROW_UNLESS(lower(i) < kInf, "Box: lower(" << i << ") is +inf (the box would be empty)");
    DVI_THROW_UNLESS(upper(i) > -kInf, "Box: upper(" << i << ") is -inf (the box would be empty)");
    finite_bounds += (lower(i) > -kInf) + (upper(i) < kInf);
  }
  auto data = std::make_shared<Data>();
  data->kind = Kind::kBox;
  data->dim = static_cast<int>(lower.size());
  data->is_box = true;
  data->is_polyhedral = true;
  data->lower = std::move(lower);
  data->upper = std::move(upper);
  data->num_inequalities = finite_bounds;
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Whole(int m) {
  DVI_THROW_UNLESS(m >= 0, "Whole dimension m = " << m << " is negative");
  return Box(Eigen::VectorXd::Constant(m, -kInf), Eigen::VectorXd::Constant(m, kInf));
}


ConvexSet ConvexSet::Ball(Eigen::VectorXd center, double radius) {
  DVI_THROW_UNLESS(std::isfinite(radius) && radius >= 0.0,
                   "Ball: radius = " << radius << " must be finite and nonnegative");
  for (Eigen::Index i = 0; i < center.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(center(i)),
                     "Ball: center(" << i << ") = " << center(i) << " is not finite");
  }
  auto data = std::make_shared<Data>();
  data->kind = Kind::kBall;
  data->dim = static_cast<int>(center.size());
  // A ball of radius 0 is the point {c}: no inequality, m equalities u = c.
  data->num_inequalities = radius > 0.0 ? 1 : 0;
  data->num_equalities = radius > 0.0 ? 0 : data->dim;
  data->center = std::move(center);
  data->radius = radius;
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Product(std::vector<ConvexSet> parts) {
  DVI_THROW_UNLESS(!parts.empty(), "Product: parts is empty");
  auto data = std::make_shared<Data>();
  data->kind = Kind::kProduct;
  data->is_box = true;
  data->is_polyhedral = true;
  for (ConvexSet& part : parts) {
    // Nested products are flattened, so every part is a leaf set.
    if (part.data_->kind == Kind::kProduct) {
      for (const ConvexSet& leaf : part.data_->parts) data->parts.push_back(leaf);
    } else {
      data->parts.push_back(std::move(part));
    }
  }
  for (const ConvexSet& part : data->parts) {
    data->offsets.push_back(data->dim);
    data->dim += part.data_->dim;
    data->is_box = data->is_box && part.data_->is_box;
    data->is_polyhedral = data->is_polyhedral && part.data_->is_polyhedral;
    data->num_inequalities += part.data_->num_inequalities;
    data->num_equalities += part.data_->num_equalities;
  }
  return ConvexSet(std::move(data));
}


// ---------------------------------------------------------------------------
// Projection.

void ConvexSet::Data::ProjectInto(const Eigen::Ref<const Eigen::VectorXd>& v,
                                  Eigen::Ref<Eigen::VectorXd> out) const {
  switch (kind) {
    case Kind::kOrthant:
      out = v.cwiseMax(0.0);
      return;
    case Kind::kBox:
      out = v.cwiseMax(lower).cwiseMin(upper);
      return;
    case Kind::kBall: {
      // stableNorm: ‖(1e300, 1e300)‖ overflows the plain sum of squares.
      const double distance = (v - center).stableNorm();
      if (distance <= radius) {
        out = v;
      } else {
        out = center + (radius / distance) * (v - center);
      }
      return;
    }
    case Kind::kPolyhedron:
      ProjectOntoPolyhedron(v, out);
      return;
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        part.ProjectInto(v.segment(offsets[k], part.dim), out.segment(offsets[k], part.dim));
      }
      return;
  }
}


// ---------------------------------------------------------------------------
// Membership, bounds, inequalities.

bool ConvexSet::Data::Contains(const Eigen::Ref<const Eigen::VectorXd>& u, double tol) const {
  // Positive conditions throughout, so that a NaN entry is never inside.
  switch (kind) {
    case Kind::kOrthant:
    case Kind::kBox:
      for (Eigen::Index i = 0; i < u.size(); ++i) {
        if (!(u(i) >= lower(i) - tol && u(i) <= upper(i) + tol)) return false;
      }
      return true;
    case Kind::kPolyhedron: {
      for (Eigen::Index i = 0; i < u.size(); ++i) {
        if (!std::isfinite(u(i))) return false;
      }
      const bool inequalities = G.rows() == 0 || (G * u - h).maxCoeff() <= tol;
      const bool equalities = E.rows() == 0 || (E * u - e).cwiseAbs().maxCoeff() <= tol;
      return inequalities && equalities;
    }
    case Kind::kBall:
      return (u - center).norm() <= radius + tol;
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        if (!part.Contains(u.segment(offsets[k], part.dim), tol)) return false;
      }
      return true;
  }
  return false;
}

void ConvexSet::Data::AppendBoxBounds(Eigen::Ref<Eigen::VectorXd> lower_out,
                                      Eigen::Ref<Eigen::VectorXd> upper_out) const {
  if (kind == Kind::kProduct) {
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const Data& part = *parts[k].data_;
      part.AppendBoxBounds(lower_out.segment(offsets[k], part.dim),
                           upper_out.segment(offsets[k], part.dim));
    }
    return;
  }
  lower_out = lower;
  upper_out = upper;
}

void ConvexSet::Data::AppendPolyhedron(Inequalities& out, int inequality_row, int equality_row,
                                       int column) const {
  switch (kind) {
    case Kind::kOrthant:
    case Kind::kBox:
      // Per component: −u_i ≤ −l_i, then u_i ≤ u_i, each when finite.
      for (int i = 0; i < dim; ++i) {
        if (lower(i) > -kInf) {
          out.G(inequality_row, column + i) = -1.0;
          out.h(inequality_row++) = -lower(i);
        }
        if (upper(i) < kInf) {
          out.G(inequality_row, column + i) = 1.0;
          out.h(inequality_row++) = upper(i);
        }
      }
      return;
    case Kind::kPolyhedron:
      out.G.block(inequality_row, column, G.rows(), dim) = G;
      out.h.segment(inequality_row, h.size()) = h;
      out.E.block(equality_row, column, E.rows(), dim) = E;
      out.e.segment(equality_row, e.size()) = e;
      return;
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        part.AppendPolyhedron(out, inequality_row, equality_row, column + offsets[k]);
        inequality_row += part.num_inequalities;
        equality_row += part.num_equalities;
      }
      return;
    case Kind::kBall:
      return;
  }
}

void ConvexSet::Data::AppendActive(const Eigen::Ref<const Eigen::VectorXd>& u, double tol,
                                   int index_offset, int column, std::vector<int>& indices,
                                   std::vector<Eigen::VectorXd>& normals,
                                   std::vector<Eigen::VectorXd>& equality_normals,
                                   int full_dim) const {
  const auto unit = [full_dim, column](int i, double sign) {
    Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
    n(column + i) = sign;
    return n;
  };
  switch (kind) {
    case Kind::kOrthant:
    case Kind::kBox: {
      int index = index_offset;
      for (int i = 0; i < dim; ++i) {
        if (lower(i) > -kInf) {
          if (std::abs(u(i) - lower(i)) <= tol) {
            indices.push_back(index);
            normals.push_back(unit(i, -1.0));
          }
          ++index;
        }
        if (upper(i) < kInf) {
          if (std::abs(u(i) - upper(i)) <= tol) {
            indices.push_back(index);
            normals.push_back(unit(i, 1.0));
          }
          ++index;
        }
      }
      return;
    }
    case Kind::kPolyhedron:
      for (int k = 0; k < G.rows(); ++k) {
        if (std::abs(G.row(k).dot(u) - h(k)) <= tol) {
          indices.push_back(index_offset + k);
          Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
          n.segment(column, dim) = G.row(k).transpose();
          normals.push_back(std::move(n));
        }
      }
      for (int k = 0; k < E.rows(); ++k) {
        Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
        n.segment(column, dim) = E.row(k).transpose();
        equality_normals.push_back(std::move(n));
      }
      return;
    case Kind::kBall: {
      if (radius == 0.0) {
        for (int i = 0; i < dim; ++i) equality_normals.push_back(unit(i, 1.0));
        return;
      }
      // g(u) = ‖u − c‖ − r, in the units of u like the other kinds' rows;
      // its gradient is the unit outward normal.
      const double distance = (u - center).norm();
      if (std::abs(distance - radius) <= tol) {
        indices.push_back(index_offset);
        Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
        n.segment(column, dim) = (u - center) / distance;
        normals.push_back(std::move(n));
      }
      return;
    }
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        part.AppendActive(u.segment(offsets[k], part.dim), tol, index_offset, column + offsets[k],
                          indices, normals, equality_normals, full_dim);
        index_offset += part.num_inequalities;
      }
      return;
  }
}

std::string ConvexSet::Data::Describe() const {
  std::ostringstream out;
  switch (kind) {
    case Kind::kPolyhedron:
      out << "polyhedron[" << dim << "; " << G.rows() << " inequalities, " << E.rows()
          << " equalities]";
      break;
    case Kind::kProduct:
      out << "product(";
      for (std::size_t k = 0; k < parts.size(); ++k) {
        out << (k > 0 ? ", " : "") << parts[k].data_->Describe();
      }
      out << ")";
      break;
    default:
      out << KindName(kind) << "[" << dim << "]";
      break;
  }
  return out.str();
}

// ---------------------------------------------------------------------------
// Public members.

ConvexSet::Kind ConvexSet::kind() const { return data_->kind; }

int ConvexSet::dim() const { return data_->dim; }

bool ConvexSet::Contains(const Eigen::VectorXd& u, double tol) const {
  DVI_THROW_UNLESS(u.size() == dim(), "Contains: u has " << u.size() << " entries, but "
                                                         << Describe() << " has dimension "
                                                         << dim());
  return data_->Contains(u, tol);
}

Eigen::VectorXd ConvexSet::Project(const Eigen::VectorXd& v) const {
  DVI_THROW_UNLESS(v.size() == dim(), "Project: v has " << v.size() << " entries, but "
                                                        << Describe() << " has dimension "
                                                        << dim());
  Eigen::VectorXd out(dim());
  data_->ProjectInto(v, out);
  return out;
}

bool ConvexSet::IsBox() const { return data_->is_box; }

std::pair<Eigen::VectorXd, Eigen::VectorXd> ConvexSet::BoxBounds() const {
  DVI_THROW_UNLESS(IsBox(), "BoxBounds: " << Describe() << " is not a box");
  std::pair<Eigen::VectorXd, Eigen::VectorXd> bounds{Eigen::VectorXd(dim()),
                                                     Eigen::VectorXd(dim())};
  data_->AppendBoxBounds(bounds.first, bounds.second);
  return bounds;
}

bool ConvexSet::IsPolyhedral() const { return data_->is_polyhedral; }

ConvexSet::Inequalities ConvexSet::AsPolyhedron() const {
  DVI_THROW_UNLESS(IsPolyhedral(), "AsPolyhedron: " << Describe() << " is not polyhedral");
  Inequalities out;
  out.G = Eigen::MatrixXd::Zero(data_->num_inequalities, dim());
  out.h = Eigen::VectorXd::Zero(data_->num_inequalities);
  out.E = Eigen::MatrixXd::Zero(data_->num_equalities, dim());
  out.e = Eigen::VectorXd::Zero(data_->num_equalities);
  data_->AppendPolyhedron(out, 0, 0, 0);
  return out;
}

ConvexSet::ActiveConstraints ConvexSet::Active(const Eigen::VectorXd& u, double tol) const {
  DVI_THROW_UNLESS(u.size() == dim(), "Active: u has " << u.size() << " entries, but " << Describe()
                                                       << " has dimension " << dim());
  DVI_THROW_UNLESS(tol >= 0.0, "Active: tol = " << tol << " must be nonnegative");
  std::vector<int> indices;
  std::vector<Eigen::VectorXd> normals;
  std::vector<Eigen::VectorXd> equality_normals;
  data_->AppendActive(u, tol, 0, 0, indices, normals, equality_normals, dim());
  ActiveConstraints active;
  active.indices = std::move(indices);
  active.normals.resize(static_cast<Eigen::Index>(normals.size()), dim());
  for (std::size_t k = 0; k < normals.size(); ++k) {
    active.normals.row(static_cast<Eigen::Index>(k)) = normals[k].transpose();
  }
  active.equality_normals.resize(static_cast<Eigen::Index>(equality_normals.size()), dim());
  for (std::size_t k = 0; k < equality_normals.size(); ++k) {
    active.equality_normals.row(static_cast<Eigen::Index>(k)) = equality_normals[k].transpose();
  }
  return active;
}

std::string ConvexSet::Describe() const { return data_->Describe(); }

const std::vector<ConvexSet>& ConvexSet::parts() const {
  DVI_THROW_UNLESS(kind() == Kind::kProduct, "parts: " << Describe() << " is not a product");
  return data_->parts;
}

const Eigen::VectorXd& ConvexSet::center() const {
  DVI_THROW_UNLESS(kind() == Kind::kBall, "center: " << Describe() << " is not a ball");
  return data_->center;
}

double ConvexSet::radius() const {
  DVI_THROW_UNLESS(kind() == Kind::kBall, "radius: " << Describe() << " is not a ball");
  return data_->radius;
}

std::string_view ToString(ConvexSet::Kind kind) {
  switch (kind) {
    case ConvexSet::Kind::kOrthant: return "orthant";
    case ConvexSet::Kind::kBox: return "box";
    case ConvexSet::Kind::kPolyhedron: return "polyhedron";
    case ConvexSet::Kind::kBall: return "ball";
    case ConvexSet::Kind::kProduct: return "product";
  }
  return "unknown";
}

}  // namespace dvi
