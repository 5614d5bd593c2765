// SPDX-License-Identifier: Apache-2.0
#include "dvi/dvi_problem.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "affine_check.hpp"
#include "check.hpp"
#include "source_breakpoints.hpp"
#include "jacobian_check.hpp"

namespace dvi {
namespace {

// Where CheckShapes evaluates the functions: the origin, clipped to K when
// K is a box (only the output sizes matter, but a u in K keeps f defined).
Eigen::VectorXd ShapeProbe(const ConvexSet& K) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(K.dim());
  if (K.IsBox()) {
    const auto [lower, upper] = K.BoxBounds();
    u = u.cwiseMax(lower).cwiseMin(upper);
  }
  return u;
}

// Forward-difference step √eps·max(1, |x_j|), as the solvers use.
const double kDifferenceStep = std::sqrt(std::numeric_limits<double>::epsilon());

// Throws when a matrix holds a NaN or an infinity, naming it and the entry.
void CheckFinite(const Eigen::MatrixXd& matrix, const char* name) {
  for (Eigen::Index j = 0; j < matrix.cols(); ++j)
    for (Eigen::Index i = 0; i < matrix.rows(); ++i)
      DVI_THROW_UNLESS(std::isfinite(matrix(i, j)),
                       name << "(" << i << ", " << j << ") = " << matrix(i, j) << " is not finite");
}

void CheckSize(const Eigen::MatrixXd& matrix, Eigen::Index rows, Eigen::Index cols,
               const char* name) {
  DVI_THROW_UNLESS(matrix.rows() == rows && matrix.cols() == cols,
                   name << ": " << matrix.rows() << "×" << matrix.cols() << ", expected " << rows
                        << "×" << cols);
}

// ∂(B(t, x) u)/∂x by forward differences of B, column by column.
void AddBuJacobian(const TimeMatrixFunction& B, double t, const Eigen::VectorXd& x,
                   const Eigen::VectorXd& u, int n, int m, Eigen::MatrixXd& Jx) {
  Eigen::MatrixXd base(n, m), shifted(n, m);
  B(t, x, base);
  const Eigen::VectorXd Bu = base * u;
  Eigen::VectorXd xs = x;
  for (int j = 0; j < n; ++j) {
    const double step = kDifferenceStep * std::max(1.0, std::abs(x[j]));
    xs[j] = x[j] + step;
    shifted.setZero();
    B(t, xs, shifted);
    Jx.col(j) += (shifted * u - Bu) / step;
    xs[j] = x[j];
  }
}

}  // namespace

void Dvi::Validate() const {
  DVI_THROW_UNLESS(n >= 1, "Dvi.n: " << n << " is not a positive state dimension");
  DVI_THROW_UNLESS(m >= 0, "Dvi.m: " << m << " is negative");
  DVI_THROW_UNLESS(static_cast<bool>(f), "Dvi.f: missing");
  DVI_THROW_UNLESS(m == 0 || static_cast<bool>(F), "Dvi.F: missing (m = " << m << ")");
  DVI_THROW_UNLESS(K.dim() == m, "Dvi.K: " << K.Describe() << " has dimension " << K.dim()
                                           << ", expected m = " << m);
  internal::ValidateBreakpoints(breakpoints, "Dvi.breakpoints");
}

void Dvi::CheckShapes(double t, const Eigen::VectorXd& x) const {
  if (x.size() != n) return;
  const Eigen::VectorXd u = ShapeProbe(K);
  const auto check_vector = [&](const TimeStateFunction& g, const char* name, int rows) {
    Eigen::VectorXd out(rows);
    g(t, x, u, out);
    DVI_THROW_UNLESS(out.size() == rows,
                     "Dvi." << name << ": wrote " << out.size() << " entries, expected " << rows);
  };
  const auto check_jacobian = [&](const TimeStateJacobian& g, const TimeStateFunction& of,
                                  const char* name, const char* of_name, int rows) {
    Eigen::MatrixXd Jx(rows, n), Ju(rows, m);
    g(t, x, u, Jx, Ju);
    DVI_THROW_UNLESS(Jx.rows() == rows && Jx.cols() == n && Ju.rows() == rows && Ju.cols() == m,
                     "Dvi." << name << ": wrote Jx " << Jx.rows() << "×" << Jx.cols() << " and Ju "
                            << Ju.rows() << "×" << Ju.cols() << ", expected " << rows << "×" << n
                            << " and " << rows << "×" << m);
    internal::CheckJacobianByDifferences(of, Jx, Ju, t, x, u, ("Dvi." + std::string(name)).c_str(),
                                         ("Dvi." + std::string(of_name)).c_str());
  };
  check_vector(f, "f", n);
  if (f_jacobian) check_jacobian(f_jacobian, f, "f_jacobian", "f", n);
  if (m == 0) return;
  check_vector(F, "F", m);
  if (F_jacobian) check_jacobian(F_jacobian, F, "F_jacobian", "F", m);
  if (F_time_derivative) check_vector(F_time_derivative, "F_time_derivative", m);
  if (F_affine_in_u) internal::CheckAffineInU(F, m, t, x, u, "Dvi.F_affine_in_u");
}

void SeparableDvi::Validate() const {
  DVI_THROW_UNLESS(n >= 1, "SeparableDvi.n: " << n << " is not a positive state dimension");
  DVI_THROW_UNLESS(m >= 0, "SeparableDvi.m: " << m << " is negative");
  DVI_THROW_UNLESS(static_cast<bool>(f), "SeparableDvi.f: missing");
  if (m > 0) {
    DVI_THROW_UNLESS(static_cast<bool>(B), "SeparableDvi.B: missing (m = " << m << ")");
    DVI_THROW_UNLESS(static_cast<bool>(G), "SeparableDvi.G: missing (m = " << m << ")");
    DVI_THROW_UNLESS(static_cast<bool>(F), "SeparableDvi.F: missing (m = " << m << ")");
  }
  DVI_THROW_UNLESS(K.dim() == m, "SeparableDvi.K: " << K.Describe() << " has dimension " << K.dim()
                                                    << ", expected m = " << m);
}

void SeparableDvi::CheckShapes(double t, const Eigen::VectorXd& x) const {
  if (x.size() != n) return;
  const Eigen::VectorXd u = ShapeProbe(K);
  const auto check = [](const auto& out, const char* name, Eigen::Index rows, Eigen::Index cols) {
    DVI_THROW_UNLESS(out.rows() == rows && out.cols() == cols,
                     "SeparableDvi." << name << ": wrote " << out.rows() << "×" << out.cols()
                                     << ", expected " << rows << "×" << cols);
  };
  Eigen::VectorXd vector(n);
  f(t, x, vector);
  check(vector, "f", n, 1);
  Eigen::MatrixXd matrix(n, n);
  if (f_jacobian) {
    f_jacobian(t, x, matrix);
    check(matrix, "f_jacobian", n, n);
  }
  if (m == 0) return;
  matrix.resize(n, m);
  B(t, x, matrix);
  check(matrix, "B", n, m);
  vector.resize(m);
  G(t, x, vector);
  check(vector, "G", m, 1);
  if (G_jacobian) {
    matrix.resize(m, n);
    G_jacobian(t, x, matrix);
    check(matrix, "G_jacobian", m, n);
  }
  vector.resize(m);
  F(u, vector);
  check(vector, "F", m, 1);
  if (F_jacobian) {
    matrix.resize(m, m);
    F_jacobian(u, matrix);
    check(matrix, "F_jacobian", m, m);
  }
}

Dvi SeparableDvi::ToDvi() const {
  Validate();
  const SeparableDvi s = *this;
  Dvi dvi;
  dvi.n = n;
  dvi.m = m;
  dvi.K = K;
  // The parts' shapes are checked where they are combined: Dvi::CheckShapes
  // sees only the sums, which a misshapen part would corrupt first.
  dvi.f = [s](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    s.f(t, x, out);
    DVI_THROW_UNLESS(out.size() == s.n,
                     "SeparableDvi.f: wrote " << out.size() << " entries, expected " << s.n);
    if (s.m == 0) return;
    Eigen::MatrixXd B(s.n, s.m);
    s.B(t, x, B);
    DVI_THROW_UNLESS(B.rows() == s.n && B.cols() == s.m,
                     "SeparableDvi.B: wrote " << B.rows() << "×" << B.cols() << ", expected "
                                              << s.n << "×" << s.m);
    out += B * u;
  };
  if (f_jacobian) {
    dvi.f_jacobian = [s](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                         Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      s.f_jacobian(t, x, Jx);
      if (s.m == 0) return;
      s.B(t, x, Ju);
      AddBuJacobian(s.B, t, x, u, s.n, s.m, Jx);
    };
  }
  if (m > 0) {
    dvi.F = [s](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                Eigen::VectorXd& out) {
      s.G(t, x, out);
      Eigen::VectorXd Fu(s.m);
      s.F(u, Fu);
      DVI_THROW_UNLESS(out.size() == s.m && Fu.size() == s.m,
                       "SeparableDvi.G, F: wrote " << out.size() << " and " << Fu.size()
                                                   << " entries, expected " << s.m);
      out += Fu;
    };
    if (G_jacobian && F_jacobian) {
      dvi.F_jacobian = [s](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                           Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
        s.G_jacobian(t, x, Jx);
        s.F_jacobian(u, Ju);
      };
    }
  }
  return dvi;
}

void SemiAffineDvi::Validate() const {
  DVI_THROW_UNLESS(static_cast<bool>(f), "SemiAffineDvi.f: missing");
  const Eigen::Index rows = B.rows(), cols = B.cols();
  DVI_THROW_UNLESS(rows >= 1, "SemiAffineDvi.B: " << rows << "×" << cols
                                                  << " has no rows (the state dimension n)");
  CheckSize(C, cols, rows, "SemiAffineDvi.C");
  CheckSize(D, cols, cols, "SemiAffineDvi.D");
  DVI_THROW_UNLESS(q.size() == 0 || q.size() == cols,
                   "SemiAffineDvi.q: " << q.size() << " entries, expected " << cols);
  CheckFinite(B, "SemiAffineDvi.B");
  CheckFinite(C, "SemiAffineDvi.C");
  CheckFinite(D, "SemiAffineDvi.D");
  CheckFinite(q, "SemiAffineDvi.q");
  DVI_THROW_UNLESS(K.dim() == cols, "SemiAffineDvi.K: " << K.Describe() << " has dimension "
                                                        << K.dim() << ", expected m = " << cols);
}

SeparableDvi SemiAffineDvi::ToSeparable() const {
  Validate();
  SeparableDvi s;
  s.n = n();
  s.m = m();
  s.K = K;
  const auto state_map = f;
  s.f = [state_map](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { state_map(x, out); };
  if (f_jacobian) {
    const auto state_jacobian = f_jacobian;
    s.f_jacobian = [state_jacobian](double, const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
      state_jacobian(x, J);
    };
  }
  const Eigen::MatrixXd B_matrix = B, C_matrix = C, D_matrix = D;
  const Eigen::VectorXd q_vector = q.size() == 0 ? Eigen::VectorXd::Zero(m()) : q;
  s.B = [B_matrix](double, const Eigen::VectorXd&, Eigen::MatrixXd& out) { out = B_matrix; };
  s.G = [C_matrix, q_vector](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    out = q_vector + C_matrix * x;
  };
  s.G_jacobian = [C_matrix](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = C_matrix; };
  s.F = [D_matrix](const Eigen::VectorXd& u, Eigen::VectorXd& out) { out = D_matrix * u; };
  s.F_jacobian = [D_matrix](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = D_matrix; };
  return s;
}

}  // namespace dvi
