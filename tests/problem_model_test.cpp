// SPDX-License-Identifier: Apache-2.0
// The problem model: validation messages, the converters between problem
// classes (semi-affine → separable → general DVI, Filippov → separable), the
// Filippov sign LCS (4.2), and the three DVI forms (2.9)–(2.11) of
// projected dynamics.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "dvi/dvi_problem.hpp"
#include "dvi/error.hpp"
#include "support/expect_throw.hpp"
#include "dvi/filippov.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "dvi/solve.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Converters only rearrange floating-point operations: a few ulps.
constexpr double kRoundOff = 1e-14;
// ∂(B(t, x) u)/∂x by forward differences with step √eps: error O(√eps).
constexpr double kDifferenceTolerance = 1e-6;

Dvi ValidDvi() {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out = -x;
  };
  dvi.F = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.K = ConvexSet::Orthant(1);
  return dvi;
}

// Validate() of a copy of `valid` changed by `change` throws naming `name`.
template <typename Problem, typename Change>
void ExpectValidateNames(const Problem& valid, const std::string& name, Change change) {
  Problem problem = valid;
  change(problem);
  ExpectThrowNaming([&] { problem.Validate(); }, name);
}

TEST(DviValidate, NamesEachField) {
  const Dvi valid = ValidDvi();
  EXPECT_NO_THROW(valid.Validate());
  ExpectValidateNames(valid, "Dvi.n", [](Dvi& d) { d.n = 0; });
  ExpectValidateNames(valid, "Dvi.m", [](Dvi& d) { d.m = -1; });
  ExpectValidateNames(valid, "Dvi.f", [](Dvi& d) { d.f = nullptr; });
  ExpectValidateNames(valid, "Dvi.F", [](Dvi& d) { d.F = nullptr; });
  ExpectValidateNames(valid, "Dvi.K", [](Dvi& d) { d.K = ConvexSet::Orthant(2); });
  // Without u, F is not needed.
  Dvi ode = valid;
  ode.m = 0;
  ode.F = nullptr;
  ode.K = ConvexSet::Orthant(0);
  EXPECT_NO_THROW(ode.Validate());
}

SeparableDvi ValidSeparable() {
  SeparableDvi s;
  s.n = 2;
  s.m = 1;
  s.f = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = -x; };
  s.B = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& B) { B.setOnes(2, 1); };
  s.G = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = x.head(1); };
  s.F = [](const Eigen::VectorXd& u, Eigen::VectorXd& out) { out = u; };
  s.K = ConvexSet::Orthant(1);
  return s;
}

TEST(SeparableDviValidate, NamesEachField) {
  using S = SeparableDvi;
  const S valid = ValidSeparable();
  EXPECT_NO_THROW(valid.Validate());
  ExpectValidateNames(valid, "SeparableDvi.n", [](S& s) { s.n = 0; });
  ExpectValidateNames(valid, "SeparableDvi.f", [](S& s) { s.f = nullptr; });
  ExpectValidateNames(valid, "SeparableDvi.B", [](S& s) { s.B = nullptr; });
  ExpectValidateNames(valid, "SeparableDvi.G", [](S& s) { s.G = nullptr; });
  ExpectValidateNames(valid, "SeparableDvi.F", [](S& s) { s.F = nullptr; });
  ExpectValidateNames(valid, "SeparableDvi.K", [](S& s) { s.K = ConvexSet::Orthant(3); });
  S no_B = valid;
  no_B.B = nullptr;
  ExpectThrowNaming([&] { no_B.ToDvi(); }, "SeparableDvi.B");
}

SemiAffineDvi ValidSemiAffine() {
  SemiAffineDvi s;
  s.f = [](const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    out.resize(2);
    out << std::sin(x[0]), x[0] * x[1];
  };
  s.f_jacobian = [](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    J.resize(2, 2);
    J << std::cos(x[0]), 0, x[1], x[0];
  };
  s.B.resize(2, 2);
  s.B << 1, -2, 0.5, 3;
  s.C.resize(2, 2);
  s.C << 0.3, 1, -1, 2;
  s.D.resize(2, 2);
  s.D << 2, 1, -1, 4;
  s.q.resize(2);
  s.q << -0.5, 0.25;
  s.K = ConvexSet::Box(Eigen::Vector2d(-1, 0), Eigen::Vector2d(1, 2));
  return s;
}

TEST(SemiAffineDviValidate, NamesEachField) {
  using S = SemiAffineDvi;
  const S valid = ValidSemiAffine();
  EXPECT_NO_THROW(valid.Validate());
  ExpectValidateNames(valid, "SemiAffineDvi.f", [](S& s) { s.f = nullptr; });
  ExpectValidateNames(valid, "SemiAffineDvi.C: 3×2, expected 2×2", [](S& s) { s.C.resize(3, 2); });
  ExpectValidateNames(valid, "SemiAffineDvi.D", [](S& s) { s.D.resize(2, 1); });
  ExpectValidateNames(valid, "SemiAffineDvi.q", [](S& s) { s.q.resize(3); });
  ExpectValidateNames(valid, "SemiAffineDvi.B(1, 0)", [](S& s) { s.B(1, 0) = kNaN; });
  ExpectValidateNames(valid, "SemiAffineDvi.K", [](S& s) { s.K = ConvexSet::Orthant(3); });
  ExpectValidateNames(valid, "SemiAffineDvi.B", [](S& s) { s.B.resize(0, 2); });
}

TEST(FilippovSystemValidate, NamesEachField) {
  using S = FilippovSystem;
  S valid;
  valid.n = 1;
  valid.k = 1;
  valid.f0 = [](double, const Eigen::VectorXd&, Eigen::VectorXd& out) { out.setZero(1); };
  valid.f1 = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setOnes(1, 1); };
  valid.h = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = x; };
  EXPECT_NO_THROW(valid.Validate());
  ExpectValidateNames(valid, "FilippovSystem.n", [](S& s) { s.n = 0; });
  ExpectValidateNames(valid, "FilippovSystem.k", [](S& s) { s.k = 0; });
  ExpectValidateNames(valid, "FilippovSystem.f0", [](S& s) { s.f0 = nullptr; });
  ExpectValidateNames(valid, "FilippovSystem.f1", [](S& s) { s.f1 = nullptr; });
  ExpectValidateNames(valid, "FilippovSystem.h", [](S& s) { s.h = nullptr; });
  S no_h = valid;
  no_h.h = nullptr;
  ExpectThrowNaming([&] { no_h.ToSeparable(); }, "FilippovSystem.h");
}

TEST(ProjectedDynamicsValidate, NamesEachField) {
  using P = ProjectedDynamics;
  const P valid =
      P::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1, 2), ConvexSet::Orthant(2));
  EXPECT_NO_THROW(valid.Validate());
  ExpectValidateNames(valid, "ProjectedDynamics.F", [](P& p) { p.F = nullptr; });
  ExpectValidateNames(valid, "ProjectedDynamics.K", [](P& p) { p.K = ConvexSet::Orthant(0); });
  ExpectThrowNaming(
      [] { P::Affine(Eigen::Matrix3d::Identity(), Eigen::Vector2d(1, 2), ConvexSet::Orthant(2)); },
      "A is 3×3, expected 2×2");
  ExpectThrowNaming(
      [] {
        P::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1, kNaN), ConvexSet::Orthant(2));
      },
      "c has a non-finite entry");
}

TEST(FilippovSignLcs, MatricesAreThoseOf42) {
  Eigen::Matrix2d E;
  E << -2, 1, 0.5, -3;
  const Eigen::Vector2d p(0.1, -0.2);
  const Lcs lcs = FilippovSignLcs(E, p);
  Eigen::MatrixXd B(2, 4), C(4, 2), D(4, 4);
  B << 2, -1, 0, 0,  //
      -0.5, 3, 0, 0;
  C << 1, 0,  //
      0, 1,   //
      0, 0,   //
      0, 0;
  D << 0, 0, 1, 0,  //
      0, 0, 0, 1,   //
      -1, 0, 0, 0,  //
      0, -1, 0, 0;
  EXPECT_EQ(Eigen::MatrixXd(lcs.A), Eigen::MatrixXd::Zero(2, 2));
  EXPECT_EQ(Eigen::MatrixXd(lcs.B), B);
  EXPECT_EQ(Eigen::MatrixXd(lcs.C), C);
  EXPECT_EQ(Eigen::MatrixXd(lcs.D), D);
  // p ← p + E1 = (0.1 − 1, −0.2 − 2.5).
  EXPECT_EQ(lcs.p, Eigen::Vector2d(-0.9, -2.7));
  EXPECT_EQ(lcs.q, Eigen::Vector4d(0, 0, 2, 2));
  EXPECT_EQ(lcs.K.dim(), 4);
  EXPECT_TRUE(lcs.K.IsBox());
  // Without p the drift is E1 alone.
  EXPECT_EQ(FilippovSignLcs(E).p, Eigen::Vector2d(-1, -2.5));

  ExpectThrowNaming([] { FilippovSignLcs(Eigen::MatrixXd::Zero(2, 3)); }, "expected square");
  ExpectThrowNaming([&] { FilippovSignLcs(E, Eigen::Vector3d::Zero()); }, "p has 3 entries");
  ExpectThrowNaming(
      [&] {
        Eigen::Matrix2d bad = E;
        bad(1, 0) = kNaN;
        FilippovSignLcs(bad);
      },
      "E(1, 0)");
  ExpectThrowNaming([] { FilippovSignFromLcs(Eigen::VectorXd::Zero(3)); }, "2n");
}

TEST(FilippovSignLcs, LcpAtAStateSelectsTheSignOfEachNonzeroComponent) {
  const Lcs lcs = FilippovSignLcs(-Eigen::Matrix3d::Identity());
  const Eigen::Vector3d x(2, -3, 0);
  const Eigen::MatrixXd D(lcs.D);
  const Eigen::VectorXd q = lcs.q + Eigen::MatrixXd(lcs.C) * x;
  const SolveResult result = Solve(Lcp{D, q});
  ASSERT_TRUE(result.solved()) << result.message;
  const Eigen::VectorXd s = FilippovSignFromLcs(result.z);
  EXPECT_NEAR(s[0], 1.0, 1e-9);
  EXPECT_NEAR(s[1], -1.0, 1e-9);
  // sgn(0) is the whole of [−1, 1] (Filippov's convexification).
  EXPECT_GE(s[2], -1.0 - 1e-9);
  EXPECT_LE(s[2], 1.0 + 1e-9);
  // x⁻ is the negative part where x ≠ 0.
  EXPECT_NEAR(result.z[3], 0.0, 1e-9);
  EXPECT_NEAR(result.z[4], 3.0, 1e-9);
}

TEST(SemiAffineDvi, ToSeparableAndToDviAgreeOnMapsAndJacobians) {
  const SemiAffineDvi semi = ValidSemiAffine();
  const SeparableDvi separable = semi.ToSeparable();
  const Dvi dvi = separable.ToDvi();
  ASSERT_EQ(dvi.n, 2);
  ASSERT_EQ(dvi.m, 2);
  EXPECT_TRUE(dvi.K.IsBox());
  const double t = 0.7;
  const Eigen::Vector2d x(0.4, -1.3), u(0.25, 1.5);

  Eigen::VectorXd fx(2), f_expected(2);
  semi.f(x, f_expected);
  f_expected += semi.B * u;
  dvi.f(t, x, u, fx);
  EXPECT_LE((fx - f_expected).lpNorm<Eigen::Infinity>(), kRoundOff);

  Eigen::VectorXd Fv(2);
  dvi.F(t, x, u, Fv);
  EXPECT_LE((Fv - (semi.q + semi.C * x + semi.D * u)).lpNorm<Eigen::Infinity>(), kRoundOff);

  ASSERT_TRUE(static_cast<bool>(dvi.f_jacobian));
  ASSERT_TRUE(static_cast<bool>(dvi.F_jacobian));
  Eigen::MatrixXd Jx(2, 2), Ju(2, 2), J_expected(2, 2);
  dvi.f_jacobian(t, x, u, Jx, Ju);
  semi.f_jacobian(x, J_expected);
  // B is constant: its difference quotient is exactly zero.
  EXPECT_LE((Jx - J_expected).lpNorm<Eigen::Infinity>(), kRoundOff);
  EXPECT_EQ(Ju, semi.B);
  dvi.F_jacobian(t, x, u, Jx, Ju);
  EXPECT_EQ(Jx, semi.C);
  EXPECT_EQ(Ju, semi.D);
}

TEST(SeparableDvi, ToDviDifferencesAStateDependentB) {
  SeparableDvi s = ValidSeparable();
  s.f_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J = -Eigen::Matrix2d::Identity();
  };
  // B(t, x) = (x0², t·x1)ᵀ: ∂(B u)/∂x = u·[[2x0, 0], [0, t]].
  s.B = [](double t, const Eigen::VectorXd& x, Eigen::MatrixXd& B) {
    B.resize(2, 1);
    B << x[0] * x[0], t * x[1];
  };
  const Dvi dvi = s.ToDvi();
  const double t = 2.0;
  const Eigen::Vector2d x(1.5, -0.5);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 3.0);
  Eigen::VectorXd fx(2);
  dvi.f(t, x, u, fx);
  EXPECT_LE((fx - Eigen::Vector2d(-1.5 + 3 * 2.25, 0.5 + 3 * -1.0)).lpNorm<Eigen::Infinity>(),
            kRoundOff);
  Eigen::MatrixXd Jx(2, 2), Ju(2, 1);
  dvi.f_jacobian(t, x, u, Jx, Ju);
  Eigen::Matrix2d expected;
  expected << -1 + 3 * 2 * 1.5, 0, 0, -1 + 3 * t;
  EXPECT_LE((Jx - expected).lpNorm<Eigen::Infinity>(), kDifferenceTolerance);
  EXPECT_EQ(Ju, Eigen::Vector2d(2.25, -1.0));
  // No G_jacobian: the general DVI gets no F_jacobian (differences later).
  EXPECT_FALSE(static_cast<bool>(dvi.F_jacobian));
}

TEST(FilippovSystem, ToSeparableIsTheSignViOnTheBox) {
  FilippovSystem system;
  system.n = 2;
  system.k = 1;
  system.f0 = [](double, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out = Eigen::Vector2d(0.3, 1);
  };
  system.f1 = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J = Eigen::Vector2d(-1, 0);
  };
  system.h = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    out = Eigen::VectorXd::Constant(1, x[0] - x[1]);
  };
  system.h_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J.resize(1, 2);
    J << 1, -1;
  };
  const SeparableDvi s = system.ToSeparable();
  ASSERT_TRUE(s.K.IsBox());
  const auto [lower, upper] = s.K.BoxBounds();
  EXPECT_EQ(lower, Eigen::VectorXd::Constant(1, -1.0));
  EXPECT_EQ(upper, Eigen::VectorXd::Constant(1, 1.0));
  const Eigen::Vector2d x(2.0, 0.5);
  Eigen::VectorXd g(1), Fu(1);
  s.G(0, x, g);
  EXPECT_EQ(g[0], -1.5);
  s.F(Eigen::VectorXd::Constant(1, 0.4), Fu);
  EXPECT_EQ(Fu[0], 0.0);
  Eigen::MatrixXd Gx(1, 2);
  s.G_jacobian(0, x, Gx);
  EXPECT_EQ(Gx(0, 0), -1.0);
  EXPECT_EQ(Gx(0, 1), 1.0);
  // h > 0 ⇒ the VI picks s = 1.
  Vi vi;
  vi.K = s.K;
  vi.F = [&](const Eigen::VectorXd& u, Eigen::VectorXd& w) {
    Eigen::VectorXd Fv(1);
    s.F(u, Fv);
    w = g + Fv;
  };
  const SolveResult result = Solve(vi);
  ASSERT_TRUE(result.solved()) << result.message;
  EXPECT_NEAR(result.z[0], 1.0, 1e-10);
}

// For each form: the multiplier u that represents the exact normal-cone
// element ν solves the form's VI at x, gives back ν, and f(t, x, u) = x'.
void ExpectFormGives(const ProjectedDynamics& pds, PdsForm form, const Dvi& dvi,
                     const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     const Eigen::VectorXd& x_dot, const Eigen::VectorXd& nu) {
  ASSERT_EQ(u.size(), dvi.m);
  Eigen::VectorXd f(dvi.n), w(dvi.m);
  dvi.f(0.0, x, u, f);
  EXPECT_LE((f - x_dot).lpNorm<Eigen::Infinity>(), kRoundOff) << f.transpose();
  dvi.F(0.0, x, u, w);
  EXPECT_LE(NaturalResidual(dvi.K, u, w), kRoundOff);
  EXPECT_LE((NormalConeElement(pds, form, x, u) - nu).lpNorm<Eigen::Infinity>(), kRoundOff);
}

TEST(ProjectedDynamicsForms, AgreeOnXDotAtABoundaryPointOfTheOrthant) {
  // x' ∈ −(x − c) − N(x; ℝ²₊) at x = (0, 1): −F = (−1, 1) points out through
  // x0 = 0, so x' = (0, 1) and ν = (−1, 0).
  const ProjectedDynamics pds = ProjectedDynamics::Affine(
      Eigen::Matrix2d::Identity(), Eigen::Vector2d(-1, 2), ConvexSet::Orthant(2));
  const Eigen::Vector2d x(0, 1), x_dot(0, 1), nu(-1, 0);
  // (2.9) with G = −I: ν = −λ.
  ExpectFormGives(pds, PdsForm::kConeDcp, ProjectedDynamicsAsConeDcp(pds), x, Eigen::Vector2d(1, 0),
                  x_dot, nu);
  ExpectFormGives(pds, PdsForm::kKkt, ProjectedDynamicsAsKkt(pds), x, Eigen::Vector2d(1, 0), x_dot,
                  nu);
  Eigen::VectorXd wy(4);
  wy << -nu, x;
  ExpectFormGives(pds, PdsForm::kAuxiliary, ProjectedDynamicsAsAuxiliary(pds), x, wy, x_dot, nu);
}

TEST(ProjectedDynamicsForms, AgreeOnXDotAtABoundaryPointOfABox) {
  // K = [0, 1]², x = (1, 0.5), F = x − (3, 0.2): −F = (2, −0.3) leaves
  // through x0 = 1, so x' = (0, −0.3) and ν = (2, 0).
  const ConvexSet box = ConvexSet::Box(Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones());
  const ProjectedDynamics pds =
      ProjectedDynamics::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(3, 0.2), box);
  const Eigen::Vector2d x(1, 0.5), x_dot(0, -0.3), nu(2, 0);
  // (2.10): the multiplier of the row x0 ≤ 1 of K's inequalities is 2.
  const ConvexSet::Inequalities rows = box.AsPolyhedron();
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(rows.G.rows());
  for (Eigen::Index k = 0; k < rows.G.rows(); ++k)
    if (rows.G.row(k) == Eigen::RowVector2d(1, 0) && rows.h[k] == 1) lambda[k] = 2;
  ASSERT_EQ(lambda.sum(), 2);
  ExpectFormGives(pds, PdsForm::kKkt, ProjectedDynamicsAsKkt(pds), x, lambda, x_dot, nu);
  Eigen::VectorXd wy(4);
  wy << -nu, x;
  ExpectFormGives(pds, PdsForm::kAuxiliary, ProjectedDynamicsAsAuxiliary(pds), x, wy, x_dot, nu);
  // A box with a nonzero bound is no cone: (2.9) does not apply.
  ExpectThrowNaming([&] { ProjectedDynamicsAsConeDcp(pds); }, "is not a cone");
}

TEST(ProjectedDynamicsForms, KktOfABallUsesTheSquaredDistance) {
  // K = unit disc, x = (1, 0), F = x − (2, 1): −F = (1, 1), x' = (0, 1),
  // ν = (1, 0) = 2u(x − 0) with u = ½.
  const ProjectedDynamics pds =
      ProjectedDynamics::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(2, 1),
                                ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0));
  const Eigen::Vector2d x(1, 0), x_dot(0, 1), nu(1, 0);
  const Dvi kkt = ProjectedDynamicsAsKkt(pds);
  ExpectFormGives(pds, PdsForm::kKkt, kkt, x, Eigen::VectorXd::Constant(1, 0.5), x_dot, nu);
  Eigen::MatrixXd Jx(1, 2), Ju(1, 1);
  kkt.F_jacobian(0.0, x, Eigen::VectorXd::Constant(1, 0.5), Jx, Ju);
  EXPECT_EQ(Jx, Eigen::RowVector2d(-2, 0));
  Eigen::VectorXd wy(4);
  wy << -nu, x;
  ExpectFormGives(pds, PdsForm::kAuxiliary, ProjectedDynamicsAsAuxiliary(pds), x, wy, x_dot, nu);

  ProjectedDynamics mixed = pds;
  mixed.K =
      ConvexSet::Product({ConvexSet::Ball(Eigen::VectorXd::Zero(1), 1.0), ConvexSet::Orthant(1)});
  ExpectThrowNaming([&] { ProjectedDynamicsAsKkt(mixed); }, "neither polyhedral nor a ball");
}

}  // namespace
}  // namespace dvi
