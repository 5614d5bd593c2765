// SPDX-License-Identifier: Apache-2.0
#include "modes/kkt_lifting.hpp"

#include <limits>
#include <memory>
#include <utility>

namespace dvi::internal {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One part of K on the block u[offset, offset + size): box bounds, linear
// constraints G u ≤ h, E u = e, or a ball; its multipliers start at
// inequality_offset in μ and equality_offset in ν.
struct Part {
  int offset = 0;
  int size = 0;
  bool is_ball = false;
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  Eigen::VectorXd center;
  double radius = 0;
  int inequality_offset = 0;
  int equality_offset = 0;
  int inequalities() const { return is_ball ? 1 : static_cast<int>(G.rows()); }
};

struct Structure {
  int m = 0;
  int inequalities = 0;
  int equalities = 0;
  Eigen::VectorXd lower;  // of z
  Eigen::VectorXd upper;
  std::vector<Part> parts;  // the non-box parts
  std::vector<int> inequality_of_mu;  // K's inequality for each μ_k
};

// Whether row (a, b) of a ≤ / = system states the same constraint as (c, d),
// up to a positive factor (or any factor, for equalities), to rounding.
bool SameConstraint(const Eigen::Ref<const Eigen::RowVectorXd>& a, double b,
                    const Eigen::Ref<const Eigen::RowVectorXd>& c, double d, bool any_sign) {
  constexpr double kSame = 64 * std::numeric_limits<double>::epsilon();
  const double na = a.lpNorm<Eigen::Infinity>(), nc = c.lpNorm<Eigen::Infinity>();
  if (na == 0 || nc == 0) return false;
  for (const double sign : {1.0, -1.0}) {
    if (sign < 0 && !any_sign) break;
    const double scale = sign * na / nc;
    if ((a - scale * c).lpNorm<Eigen::Infinity>() <= kSame * na &&
        std::abs(b - scale * d) <= kSame * std::max(std::abs(b), na))
      return true;
  }
  return false;
}

// Drops the rows of A u ≤ b (or = b) that repeat an earlier one, and the
// zero rows that constrain nothing (0 ≤ b_i, or 0 = 0): where a repeated
// row is active its multipliers are not unique (LICQ fails), the lifted
// mode matrix is singular, and the run failed where K itself is fine.
// Returns the kept rows' indices.
std::vector<int> KeepDistinctRows(Eigen::MatrixXd& A, Eigen::VectorXd& b, bool equalities) {
  std::vector<int> kept;
  for (int i = 0; i < A.rows(); ++i) {
    const bool zero_row = A.row(i).lpNorm<Eigen::Infinity>() == 0 &&
                          (equalities ? b(i) == 0 : b(i) >= 0);
    bool repeated = false;
    for (const int j : kept)
      repeated = repeated || SameConstraint(A.row(i), b(i), A.row(j), b(j), equalities);
    if (!zero_row && !repeated) kept.push_back(i);
  }
  A = A(kept, Eigen::all).eval();
  b = b(kept).eval();
  return kept;
}

Structure Analyse(const ConvexSet& K) {
  Structure s;
  s.m = K.dim();
  std::vector<ConvexSet> sets =
      K.kind() == ConvexSet::Kind::kProduct ? K.parts() : std::vector<ConvexSet>{K};
  Eigen::VectorXd u_lower = Eigen::VectorXd::Constant(s.m, -kInfinity);
  Eigen::VectorXd u_upper = Eigen::VectorXd::Constant(s.m, kInfinity);
  int offset = 0;
  int original_inequalities = 0;
  for (const ConvexSet& set : sets) {
    const int size = set.dim();
    if (set.IsBox()) {
      const auto [lower, upper] = set.BoxBounds();
      u_lower.segment(offset, size) = lower;
      u_upper.segment(offset, size) = upper;
    } else {
      Part part;
      part.offset = offset;
      part.size = size;
      if (set.kind() == ConvexSet::Kind::kBall) {
        s.inequality_of_mu.push_back(original_inequalities++);
        part.is_ball = true;
        part.center = set.center();
        part.radius = set.radius();
      } else {
        ConvexSet::Inequalities inequalities = set.AsPolyhedron();
        part.G = std::move(inequalities.G);
        part.h = std::move(inequalities.h);
        part.E = std::move(inequalities.E);
        part.e = std::move(inequalities.e);
        const int rows = static_cast<int>(part.G.rows());
        for (const int row : KeepDistinctRows(part.G, part.h, false))
          s.inequality_of_mu.push_back(original_inequalities + row);
        KeepDistinctRows(part.E, part.e, true);
        original_inequalities += rows;
      }
      part.inequality_offset = s.inequalities;
      part.equality_offset = s.equalities;
      s.inequalities += part.inequalities();
      s.equalities += static_cast<int>(part.E.rows());
      s.parts.push_back(std::move(part));
    }
    offset += size;
  }
  const int dim = s.m + s.inequalities + s.equalities;
  s.lower = Eigen::VectorXd::Constant(dim, -kInfinity);
  s.upper = Eigen::VectorXd::Constant(dim, kInfinity);
  s.lower.head(s.m) = u_lower;
  s.upper.head(s.m) = u_upper;
  s.lower.segment(s.m, s.inequalities).setZero();
  return s;
}

// F̃ and its z-Jacobian on top of F(t, x, u) and F_u.
void AddKktTerms(const Structure& s, const Eigen::VectorXd& z, Eigen::VectorXd& out,
                 Eigen::MatrixXd* Jz) {
  const int mu0 = s.m, nu0 = s.m + s.inequalities;
  for (const Part& p : s.parts) {
    const auto u = z.segment(p.offset, p.size);
    if (p.is_ball) {
      // d = u − centre as an expression: this runs at every F evaluation,
      // where a vector would be an allocation.
      const double mu = z(mu0 + p.inequality_offset);
      const auto d = u - p.center;
      out.segment(p.offset, p.size) += mu * d;
      out(mu0 + p.inequality_offset) = 0.5 * (p.radius * p.radius - d.squaredNorm());
      if (Jz) {
        Jz->block(p.offset, p.offset, p.size, p.size).diagonal().array() += mu;
        Jz->block(p.offset, mu0 + p.inequality_offset, p.size, 1) = d;
        Jz->block(mu0 + p.inequality_offset, p.offset, 1, p.size) = -d.transpose();
      }
      continue;
    }
    const int k = p.inequalities(), q = static_cast<int>(p.E.rows());
    const auto mu = z.segment(mu0 + p.inequality_offset, k);
    const auto nu = z.segment(nu0 + p.equality_offset, q);
    out.segment(p.offset, p.size) += p.G.transpose() * mu + p.E.transpose() * nu;
    out.segment(mu0 + p.inequality_offset, k) = p.h - p.G * u;
    out.segment(nu0 + p.equality_offset, q) = p.E * u - p.e;
    if (Jz) {
      Jz->block(p.offset, mu0 + p.inequality_offset, p.size, k) = p.G.transpose();
      Jz->block(p.offset, nu0 + p.equality_offset, p.size, q) = p.E.transpose();
      Jz->block(mu0 + p.inequality_offset, p.offset, k, p.size) = -p.G;
      Jz->block(nu0 + p.equality_offset, p.offset, q, p.size) = p.E;
    }
  }
}

}  // namespace

// u and F's blocks for the lifted functions, kept between calls so that an
// evaluation (several per Newton step) does not allocate. A lifted Dvi
// belongs to one integration, which calls its functions one at a time.
struct Scratch {
  Eigen::VectorXd u;
  Eigen::VectorXd head;
  Eigen::MatrixXd Fx;
  Eigen::MatrixXd Fu;
  Eigen::VectorXd unused_values;  // F̃, which AddKktTerms writes with the Jacobian
  // u for f and its Jacobian, and f_u (f's calls may interleave F's).
  Eigen::VectorXd f_input;
  Eigen::MatrixXd f_u;
};

KktLifting LiftToBox(const Dvi& dvi) {
  auto s = std::make_shared<const Structure>(Analyse(dvi.K));
  auto scratch = std::make_shared<Scratch>();
  KktLifting lifting;
  lifting.m = s->m;
  lifting.inequality_of_mu = s->inequality_of_mu;
  const int dim = static_cast<int>(s->lower.size());
  Dvi& lifted = lifting.dvi;
  lifted.n = dvi.n;
  lifted.m = dim;
  lifted.K = ConvexSet::Box(s->lower, s->upper);
  const int m = s->m;
  lifted.f = [f = dvi.f, m, scratch](double t, const Eigen::VectorXd& x,
                                     const Eigen::VectorXd& z, Eigen::VectorXd& out) {
    scratch->f_input = z.head(m);
    f(t, x, scratch->f_input, out);
  };
  if (dvi.f_jacobian) {
    lifted.f_jacobian = [J = dvi.f_jacobian, m, scratch](double t, const Eigen::VectorXd& x,
                                                         const Eigen::VectorXd& z,
                                                         Eigen::MatrixXd& Jx, Eigen::MatrixXd& Jz) {
      scratch->f_input = z.head(m);
      scratch->f_u.resize(Jx.rows(), m);
      J(t, x, scratch->f_input, Jx, scratch->f_u);
      Jz.setZero();
      Jz.leftCols(m) = scratch->f_u;
    };
  }
  lifted.F = [F = dvi.F, s, scratch](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& z,
                                     Eigen::VectorXd& out) {
    scratch->u = z.head(s->m);
    scratch->head.resize(s->m);
    F(t, x, scratch->u, scratch->head);
    out.setZero();
    out.head(s->m) = scratch->head;
    AddKktTerms(*s, z, out, nullptr);
  };
  if (dvi.F_jacobian) {
    lifted.F_jacobian = [J = dvi.F_jacobian, s, scratch](
                            double t, const Eigen::VectorXd& x, const Eigen::VectorXd& z,
                            Eigen::MatrixXd& Jx, Eigen::MatrixXd& Jz) {
      scratch->u = z.head(s->m);
      scratch->Fx.resize(s->m, x.size());
      scratch->Fu.resize(s->m, s->m);
      J(t, x, scratch->u, scratch->Fx, scratch->Fu);
      Jx.setZero();
      Jx.topRows(s->m) = scratch->Fx;
      Jz.setZero();
      Jz.topLeftCorner(s->m, s->m) = scratch->Fu;
      scratch->unused_values.setZero(z.size());
      AddKktTerms(*s, z, scratch->unused_values, &Jz);
    };
  }
  if (dvi.F_time_derivative) {
    lifted.F_time_derivative = [Ft = dvi.F_time_derivative, s](
                                   double t, const Eigen::VectorXd& x, const Eigen::VectorXd& z,
                                   Eigen::VectorXd& out) {
      Eigen::VectorXd head(s->m);
      Ft(t, x, z.head(s->m), head);
      out.setZero();
      out.head(s->m) = head;
    };
  }
  return lifting;
}

namespace {

// u between samples of the lifted run: the head of its multiplier z.
class UnliftedMultipliers final : public DenseMultipliers {
 public:
  UnliftedMultipliers(std::shared_ptr<const DenseMultipliers> lifted, int m)
      : lifted_(std::move(lifted)), m_(m) {}
  bool Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const override {
    Eigen::VectorXd z;
    if (!lifted_->Multiplier(t, x, z)) return false;
    u = z.head(m_);
    return true;
  }

 private:
  std::shared_ptr<const DenseMultipliers> lifted_;
  int m_;
};

}  // namespace

Trajectory Unlift(Trajectory lifted, const KktLifting& lifting) {
  if (lifted.dense_multipliers)
    lifted.dense_multipliers =
        std::make_shared<const UnliftedMultipliers>(std::move(lifted.dense_multipliers), lifting.m);
  VectorSamples u;
  u.reserve(lifted.multipliers.size(), lifting.m);
  for (const auto z : lifted.multipliers) u.push_back(z.head(lifting.m));
  lifted.multipliers = std::move(u);
  for (Event& event : lifted.events) {
    // Bound events of u itself, and the user's (whose index is k, not a
    // component of z), stay as they are.
    const bool bound = event.kind == EventKind::kLeftBound ||
                       event.kind == EventKind::kReachedLower ||
                       event.kind == EventKind::kReachedUpper;
    if (!bound || event.index < lifting.m) continue;
    // μ_k leaving 0 makes constraint k active; reaching 0 releases it (ν
    // has no bounds, so no events).
    event.kind = event.kind == EventKind::kLeftBound ? EventKind::kConstraintActive
                                                     : EventKind::kConstraintReleased;
    event.index = lifting.inequality_of_mu[static_cast<std::size_t>(event.index - lifting.m)];
  }
  return lifted;
}

ObservationOptions UnliftObservation(ObservationOptions observation, const KktLifting& lifting) {
  const int m = lifting.m;
  if (observation.observer)
    observation.observer = [observer = std::move(observation.observer), m](const Observation& z) {
      return observer(Observation{z.t, z.x, z.u.head(m), z.mode, z.point});
    };
  if (observation.user_events.g)
    observation.user_events.g = [g = std::move(observation.user_events.g), m](
                                    double t, const Eigen::VectorXd& x, const Eigen::VectorXd& z) {
      return g(t, x, Eigen::VectorXd(z.head(m)));
    };
  return observation;
}

}  // namespace dvi::internal
