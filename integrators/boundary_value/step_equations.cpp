// SPDX-License-Identifier: Apache-2.0
#include "step_equations.hpp"

#include <utility>

#include "forward_differences.hpp"

namespace dvi::internal {
namespace {

class DviStep final : public StepEquations {
 public:
  DviStep(Dvi dvi, double theta, bool vi_at_old_state)
      : dvi_(std::move(dvi)), theta_(theta), vi_at_old_state_(vi_at_old_state),
        f_(dvi_.n), F_(dvi_.m) {}

  void Evaluate(double t, double h, const ConstRef& x_old, const ConstRef& x_new,
                const ConstRef& u, Eigen::Ref<Eigen::VectorXd> out) override {
    const int n = dvi_.n, m = dvi_.m;
    Load(x_old, x_new, u);
    dvi_.f(t + h, x_theta_, u_, f_);
    out.head(n) = x_new - x_old - h * f_;
    if (m == 0) return;
    dvi_.F(vi_at_old_state_ ? t : t + h, x_vi_, u_, F_);
    out.tail(m) = F_;
  }

  void Jacobian(double t, double h, const ConstRef& x_old, const ConstRef& x_new, const ConstRef& u,
                Eigen::Ref<Eigen::MatrixXd> J) override {
    const int n = dvi_.n, m = dvi_.m;
    Load(x_old, x_new, u);
    J.setZero();
    Jacobians(dvi_.f, dvi_.f_jacobian, n, t + h, x_theta_, u_, fx_, fu_);
    J.block(0, 0, n, n) = -h * theta_ * fx_;
    J.block(0, 0, n, n).diagonal().array() -= 1;
    J.block(0, n, n, n) = -h * (1 - theta_) * fx_;
    J.block(0, n, n, n).diagonal().array() += 1;
    J.block(0, 2 * n, n, m) = -h * fu_;
    if (m == 0) return;
    Jacobians(dvi_.F, dvi_.F_jacobian, m, vi_at_old_state_ ? t : t + h, x_vi_, u_, Fx_, Fu_);
    J.block(n, vi_at_old_state_ ? 0 : n, m, n) = Fx_;
    J.block(n, 2 * n, m, m) = Fu_;
  }

 private:
  void Load(const ConstRef& x_old, const ConstRef& x_new, const ConstRef& u) {
    x_theta_ = theta_ * x_old + (1 - theta_) * x_new;
    x_vi_ = vi_at_old_state_ ? x_old : x_new;
    u_ = u;
  }

  Dvi dvi_;
  double theta_;
  bool vi_at_old_state_;
  Eigen::VectorXd x_theta_, x_vi_, u_, f_, F_;
  Eigen::MatrixXd fx_, fu_, Fx_, Fu_;
};

class SeparableStep final : public StepEquations {
 public:
  SeparableStep(SeparableDvi dvi, double theta, bool vi_at_old_state)
      : dvi_(std::move(dvi)), theta_(theta), vi_at_old_state_(vi_at_old_state),
        f_(dvi_.n), G_(dvi_.m), F_(dvi_.m), B_(dvi_.n, dvi_.m) {
    // g(t, x, ·) views of the parts, for forward differences.
    drift_ = [this](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                    Eigen::VectorXd& out) { dvi_.f(t, x, out); };
    input_ = [this](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                    Eigen::VectorXd& out) {
      dvi_.B(t, x, input_B_);
      out.noalias() = input_B_ * u;
    };
    coupling_ = [this](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                       Eigen::VectorXd& out) { dvi_.G(t, x, out); };
    input_B_.resize(dvi_.n, dvi_.m);
  }

  void Evaluate(double t, double h, const ConstRef& x_old, const ConstRef& x_new,
                const ConstRef& u, Eigen::Ref<Eigen::VectorXd> out) override {
    const int n = dvi_.n, m = dvi_.m;
    Load(x_old, x_new, u);
    dvi_.f(t + h, x_theta_, f_);
    out.head(n) = x_new - x_old - h * f_;
    if (m == 0) return;
    dvi_.B(t, x_old_, B_);
    out.head(n).noalias() -= h * (B_ * u_);
    dvi_.G(vi_at_old_state_ ? t : t + h, vi_at_old_state_ ? x_old_ : x_new_, G_);
    dvi_.F(u_, F_);
    out.tail(m) = G_ + F_;
  }

  void Jacobian(double t, double h, const ConstRef& x_old, const ConstRef& x_new, const ConstRef& u,
                Eigen::Ref<Eigen::MatrixXd> J) override {
    const int n = dvi_.n, m = dvi_.m;
    Load(x_old, x_new, u);
    J.setZero();
    fx_.resize(n, n);
    if (dvi_.f_jacobian) {
      dvi_.f_jacobian(t + h, x_theta_, fx_);
    } else {
      dvi_.f(t + h, x_theta_, f_);
      ForwardDifferences(drift_, n, t + h, x_theta_, empty_, f_, &fx_, empty_jacobian_);
    }
    J.block(0, 0, n, n) = -h * theta_ * fx_;
    J.block(0, 0, n, n).diagonal().array() -= 1;
    J.block(0, n, n, n) = -h * (1 - theta_) * fx_;
    J.block(0, n, n, n).diagonal().array() += 1;
    if (m == 0) return;
    // B(t_i, x^i) u^{i+1}: ∂/∂x^i by differences, ∂/∂u = B.
    Eigen::VectorXd base(n);
    input_(t, x_old_, u_, base);
    Bux_.resize(n, n);
    Bu_unused_.resize(n, m);
    ForwardDifferences(input_, n, t, x_old_, u_, base, &Bux_, Bu_unused_);
    J.block(0, 0, n, n) -= h * Bux_;
    dvi_.B(t, x_old_, B_);
    J.block(0, 2 * n, n, m) = -h * B_;
    const double t_vi = vi_at_old_state_ ? t : t + h;
    const Eigen::VectorXd& x_vi = vi_at_old_state_ ? x_old_ : x_new_;
    Gx_.resize(m, n);
    if (dvi_.G_jacobian) {
      dvi_.G_jacobian(t_vi, x_vi, Gx_);
    } else {
      dvi_.G(t_vi, x_vi, G_);
      ForwardDifferences(coupling_, m, t_vi, x_vi, empty_, G_, &Gx_, empty_jacobian_);
    }
    J.block(n, vi_at_old_state_ ? 0 : n, m, n) = Gx_;
    Fu_.resize(m, m);
    if (dvi_.F_jacobian) {
      dvi_.F_jacobian(u_, Fu_);
    } else {
      const TimeStateFunction map = [this](double, const Eigen::VectorXd&, const Eigen::VectorXd& v,
                                           Eigen::VectorXd& out) { dvi_.F(v, out); };
      dvi_.F(u_, F_);
      ForwardDifferences(map, m, 0, empty_, u_, F_, nullptr, Fu_);
    }
    J.block(n, 2 * n, m, m) = Fu_;
  }

 private:
  void Load(const ConstRef& x_old, const ConstRef& x_new, const ConstRef& u) {
    x_old_ = x_old;
    x_new_ = x_new;
    x_theta_ = theta_ * x_old + (1 - theta_) * x_new;
    u_ = u;
  }

  SeparableDvi dvi_;
  double theta_;
  bool vi_at_old_state_;
  TimeStateFunction drift_, input_, coupling_;
  Eigen::VectorXd x_old_, x_new_, x_theta_, u_, f_, G_, F_, empty_;
  Eigen::MatrixXd B_, input_B_, fx_, Bux_, Bu_unused_, Gx_, Fu_, empty_jacobian_;
};

}  // namespace

std::shared_ptr<StepEquations> MakeDviStep(const Dvi& dvi, double theta, bool vi_at_old_state) {
  return std::make_shared<DviStep>(dvi, theta, vi_at_old_state);
}

std::shared_ptr<StepEquations> MakeSeparableStep(const SeparableDvi& dvi, double theta,
                                                 bool vi_at_old_state) {
  return std::make_shared<SeparableStep>(dvi, theta, vi_at_old_state);
}

}  // namespace dvi::internal
