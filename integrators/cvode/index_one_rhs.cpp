// SPDX-License-Identifier: Apache-2.0
#include "dvi/adapters/index_one_rhs.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include "check.hpp"
#include "cvode/index_one_rhs_access.hpp"
#include "modes/box_mode.hpp"
#include "modes/kkt_lifting.hpp"

namespace dvi {
namespace {

// The problem on a box: dvi itself, or the KKT system of its VI in
// z = (u, μ, ν) when K has polyhedral or ball parts (kkt_lifting.hpp).
Dvi OnABox(const Dvi& dvi, const SolverOptions& solver) {
  dvi.Validate();
  solver.Validate();
  return dvi.K.IsBox() ? dvi : internal::LiftToBox(dvi).dvi;
}

Dvi ValidatedDvi(const Lcs& lcs) {
  lcs.Validate();
  return lcs.ToDvi();
}

}  // namespace

struct IndexOneRhs::Impl {
  Impl(Dvi problem, TimeStateFunction given_F, int u_size, const SolverOptions& solver)
      : dvi(std::move(problem)),
        F(std::move(given_F)),
        m(u_size),
        lower(dvi.K.BoxBounds().first),
        upper(dvi.K.BoxBounds().second),
        tolerance(solver.tolerance),
        system(dvi, lower, upper, solver, false),
        u(Eigen::VectorXd::Zero(dvi.m)) {}

  void CheckState(const Eigen::VectorXd& x) const {
    DVI_THROW_UNLESS(x.size() == dvi.n, "x has " << x.size() << " entries, expected " << dvi.n);
  }
  bool InMode(double t, const Eigen::VectorXd& x);
  bool Select(double t, const Eigen::VectorXd& x);
  bool Update(double t, const Eigen::VectorXd& x);

  // The Dvi is owned: BoxModeSystem keeps a reference to it, and an Lcs's
  // Dvi and a lifted one are temporaries. Its multiplier is z, of which u is
  // the first m components.
  const Dvi dvi;
  // F of the problem as given, for w(); the lifted dvi's F differs.
  const TimeStateFunction F;
  const int m;
  const Eigen::VectorXd lower;
  const Eigen::VectorXd upper;
  const double tolerance;
  internal::BoxModeSystem system;
  Eigen::VectorXd u;
  // Where u was last computed, for w().
  double t_u = 0;
  Eigen::VectorXd x_u;
  Mode mode;
  bool has_mode = false;
  bool frozen = false;
  // Whether system.u() solves the mode at the last (t, x), which the
  // Jacobian needs (after a selection whose mode Newton failed, u is the VI's).
  bool mode_solved = false;
  std::string message;
  IndexOneRhsStats stats;
};

// The mode's root functions (box_mode.hpp) non-negative up to the VI
// tolerance: a free u_j inside its bounds, a bound component's F_j of the
// sign that holds it there. The slack keeps a degenerate component (F_j ≈ 0
// at a bound) from forcing a VI solve at every evaluation; its effect on u
// is within the tolerance a VI solve would leave anyway.
bool IndexOneRhs::Impl::InMode(double t, const Eigen::VectorXd& x) {
  std::vector<double> roots(2 * static_cast<std::size_t>(dvi.m));
  system.Roots(t, x, roots.data());
  for (const double g : roots)
    if (!(g >= -tolerance)) return false;
  return true;
}

bool IndexOneRhs::Impl::Select(double t, const Eigen::VectorXd& x) {
  t_u = t;
  x_u = x;
  if (dvi.m == 0) {  // an ODE: no VI (and F may be unset)
    has_mode = true;
    mode_solved = true;
    return true;
  }
  const SolveResult vi = system.problem().SolveVi(t, x, u);
  ++stats.vi_solves;
  if (!vi.solved()) {
    std::ostringstream text;
    text << "IndexOneRhs: the VI at t = " << t << " is not solved (" << ToString(vi.status)
         << ", residual " << vi.residual << "): " << vi.message;
    message = text.str();
    return false;
  }
  // A component within the tolerance of a bound is taken there: u is
  // Lipschitz, so a degenerate component (the β set of Sect. 5.3) has the
  // same u in either neighbouring mode.
  Mode selected(dvi.m, MultiplierBound::kFree);
  for (int j = 0; j < dvi.m; ++j) {
    const double to_lower = vi.z(j) - lower(j), to_upper = upper(j) - vi.z(j);
    if (to_lower <= tolerance && to_lower <= to_upper)
      selected[j] = MultiplierBound::kLower;
    else if (to_upper <= tolerance)
      selected[j] = MultiplierBound::kUpper;
  }
  if (has_mode && selected != mode) ++stats.mode_changes;
  mode = std::move(selected);
  has_mode = true;
  system.Enter(mode, vi.z);
  // The mode's Newton polishes u to round-off, so that u is smooth along the
  // flow; if it fails, the VI's u is as good to the tolerance.
  mode_solved = system.Solve(t, x);
  u = mode_solved ? system.u() : vi.z;
  return true;
}

bool IndexOneRhs::Impl::Update(double t, const Eigen::VectorXd& x) {
  t_u = t;
  x_u = x;
  if (!has_mode) return Select(t, x);
  std::string why;
  mode_solved = system.Solve(t, x, &why);
  if (mode_solved && (frozen || InMode(t, x))) {
    u = system.u();
    return true;
  }
  if (!frozen) return Select(t, x);
  std::ostringstream text;
  text << "IndexOneRhs: frozen mode " << ModeLetters(mode) << " at t = " << t << ": " << why;
  message = text.str();
  return false;
}

IndexOneRhs::IndexOneRhs(const Dvi& dvi, const SolverOptions& solver)
    : impl_(std::make_unique<Impl>(OnABox(dvi, solver), dvi.F, dvi.m, solver)) {}

IndexOneRhs::IndexOneRhs(const Lcs& lcs, const SolverOptions& solver)
    : IndexOneRhs(ValidatedDvi(lcs), solver) {}

IndexOneRhs::IndexOneRhs(const SeparableDvi& dvi, const SolverOptions& solver)
    : IndexOneRhs((dvi.Validate(), dvi.ToDvi()), solver) {}

IndexOneRhs::IndexOneRhs(const SemiAffineDvi& dvi, const SolverOptions& solver)
    : IndexOneRhs((dvi.Validate(), dvi.ToSeparable()), solver) {}

IndexOneRhs::~IndexOneRhs() = default;
IndexOneRhs::IndexOneRhs(IndexOneRhs&&) noexcept = default;
IndexOneRhs& IndexOneRhs::operator=(IndexOneRhs&&) noexcept = default;

int IndexOneRhs::n() const { return impl_->dvi.n; }
int IndexOneRhs::m() const { return impl_->m; }
int IndexOneRhs::mode_size() const { return impl_->dvi.m; }

bool IndexOneRhs::Evaluate(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot) {
  Impl& impl = *impl_;
  impl.CheckState(x);
  ++impl.stats.rhs_evals;
  if (!impl.Update(t, x)) return false;
  xdot.resize(impl.dvi.n);
  impl.dvi.f(t, x, impl.u, xdot);
  if (!xdot.allFinite()) {
    std::ostringstream text;
    text << "IndexOneRhs: f is not finite at t = " << t;
    impl.message = text.str();
    return false;
  }
  return true;
}

bool IndexOneRhs::Jacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
  Impl& impl = *impl_;
  impl.CheckState(x);
  ++impl.stats.jacobian_evals;
  if (!impl.Update(t, x)) return false;
  const auto fail = [&](const char* why) {
    std::ostringstream text;
    text << "IndexOneRhs: mode " << ModeLetters(impl.mode) << " at t = " << t << ": " << why;
    impl.message = text.str();
    return false;
  };
  if (!impl.mode_solved)
    return fail("Newton on the free components did not converge, so du/dx is unknown");
  // f_x + f_u du/dx with du_A/dx = −F_u[A, A]⁻¹ F_x[A, :] (box_mode.hpp).
  if (!impl.system.RhsJacobian(t, x, J)) return fail("∂F/∂u on the free components is singular");
  return true;
}

Eigen::VectorXd IndexOneRhs::multiplier() const { return impl_->u.head(impl_->m); }
Eigen::VectorXd IndexOneRhs::w() const {
  const Impl& impl = *impl_;
  if (impl.x_u.size() == 0 || impl.m == 0) return Eigen::VectorXd(0);
  Eigen::VectorXd w(impl.m);
  impl.F(impl.t_u, impl.x_u, impl.u.head(impl.m), w);
  return w;
}

const std::string& IndexOneRhs::message() const { return impl_->message; }

const Mode& IndexOneRhs::mode() const { return impl_->mode; }

bool IndexOneRhs::SelectMode(double t, const Eigen::VectorXd& x) {
  impl_->CheckState(x);
  return impl_->Select(t, x);
}

void IndexOneRhs::EnterMode(const Mode& mode, const Eigen::VectorXd& u) {
  Impl& impl = *impl_;
  const int size = impl.dvi.m;
  DVI_THROW_UNLESS(static_cast<int>(mode.size()) == size,
                   "mode has " << mode.size() << " entries, expected " << size);
  DVI_THROW_UNLESS(u.size() == impl.m || u.size() == size,
                   "u has " << u.size() << " entries, expected " << impl.m
                            << (size == impl.m ? "" : " or " + std::to_string(size)));
  for (int j = 0; j < u.size(); ++j)
    DVI_THROW_UNLESS(std::isfinite(u(j)), "u(" << j << ") = " << u(j) << " is not finite");
  // K's multipliers μ, ν, when not given, start from their last values.
  Eigen::VectorXd z = impl.u;
  z.head(u.size()) = u;
  for (int j = 0; j < size; ++j) {
    DVI_THROW_UNLESS(mode[j] == MultiplierBound::kFree || mode[j] == MultiplierBound::kLower ||
                         mode[j] == MultiplierBound::kUpper,
                     "mode[" << j << "]: " << static_cast<int>(mode[j])
                             << " is not a MultiplierBound");
    DVI_THROW_UNLESS(mode[j] != MultiplierBound::kLower || std::isfinite(impl.lower(j)),
                     "mode[" << j << "]: at the lower bound, which is " << impl.lower(j));
    DVI_THROW_UNLESS(mode[j] != MultiplierBound::kUpper || std::isfinite(impl.upper(j)),
                     "mode[" << j << "]: at the upper bound, which is " << impl.upper(j));
  }
  impl.system.Enter(mode, z);
  impl.mode = mode;
  impl.has_mode = true;
  impl.mode_solved = false;
}

void IndexOneRhs::FreezeMode(bool frozen) { impl_->frozen = frozen; }
bool IndexOneRhs::mode_frozen() const { return impl_->frozen; }

int IndexOneRhs::root_count() const { return 2 * impl_->dvi.m; }

bool IndexOneRhs::ModeRoots(double t, const Eigen::VectorXd& x, double* g) {
  Impl& impl = *impl_;
  impl.CheckState(x);
  if (impl.dvi.m == 0) return true;
  if (!impl.has_mode) {
    impl.message = "IndexOneRhs: ModeRoots before any mode is known (SelectMode or EnterMode first)";
    return false;
  }
  std::string why;
  impl.mode_solved = impl.system.Solve(t, x, &why);
  if (!impl.mode_solved) {
    std::ostringstream text;
    text << "IndexOneRhs: mode " << ModeLetters(impl.mode) << " at t = " << t << ": " << why;
    impl.message = text.str();
    return false;
  }
  impl.u = impl.system.u();
  impl.t_u = t;
  impl.x_u = x;
  impl.system.Roots(t, x, g);
  return true;
}

void IndexOneRhs::CrossRoots(const int* crossed) {
  Impl& impl = *impl_;
  DVI_THROW_UNLESS(impl.has_mode, "IndexOneRhs::CrossRoots before any mode is known");
  Mode next = impl.mode;
  for (std::size_t j = 0; j < next.size(); ++j) {
    if (crossed[2 * j] == 0 && crossed[2 * j + 1] == 0) continue;
    if (next[j] != MultiplierBound::kFree)
      next[j] = MultiplierBound::kFree;
    else
      next[j] = crossed[2 * j] != 0 ? MultiplierBound::kLower : MultiplierBound::kUpper;
  }
  if (next != impl.mode) ++impl.stats.mode_changes;
  const Eigen::VectorXd z = impl.u;
  EnterMode(next, z);
}

IndexOneRhsStats IndexOneRhs::stats() const {
  IndexOneRhsStats stats = impl_->stats;
  stats.newton_iterations = impl_->system.newton_iterations();
  return stats;
}

void internal::IndexOneRhsAccess::SetMessage(IndexOneRhs& rhs, std::string message) {
  rhs.impl_->message = std::move(message);
}

}  // namespace dvi
