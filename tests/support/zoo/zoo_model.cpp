// SPDX-License-Identifier: Apache-2.0
#include "support/zoo/zoo_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

Eigen::VectorXd ZooModel::P(double t) const {
  return p_source ? Eigen::VectorXd(lcs.p + p_source(t)) : lcs.p;
}

Eigen::VectorXd ZooModel::Q(double t) const {
  return q_source ? Eigen::VectorXd(lcs.q + q_source(t)) : lcs.q;
}

Eigen::VectorXd ZooModel::F(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) const {
  return lcs.A * x + lcs.B * u + P(t);
}

Eigen::VectorXd ZooModel::W(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) const {
  return lcs.C * x + lcs.D * u + Q(t);
}

OrthantLcs ToOrthant(const Lcs& lcs) {
  const int m = lcs.m();
  if (!lcs.K.IsBox()) throw std::invalid_argument("ToOrthant: K is not a box");
  const auto [lower, upper] = lcs.K.BoxBounds();
  std::vector<int> split;  // components with a second pair: boxed or free
  for (int j = 0; j < m; ++j) {
    const bool boxed = std::isfinite(lower(j)) && std::isfinite(upper(j));
    const bool free = lower(j) == -HUGE_VAL && upper(j) == HUGE_VAL;
    if (boxed || free) {
      split.push_back(j);
    } else if (!(lower(j) == 0 && upper(j) == HUGE_VAL)) {
      throw std::invalid_argument("ToOrthant: u" + std::to_string(j + 1) +
                                  " is neither in [0, ∞), in a finite interval nor free");
    }
  }
  const int k = static_cast<int>(split.size()), mo = m + k;
  // u = U ũ + c, and w̃ = R (C x + D u + q) + E ũ + e: R flips a box row's
  // sign (its pair is v_j ⊥ z_j − F_j) and copies a free row, negated, to
  // its second pair.
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(m, mo), R = Eigen::MatrixXd::Zero(mo, m),
                  E = Eigen::MatrixXd::Zero(mo, mo);
  Eigen::VectorXd offset = Eigen::VectorXd::Zero(m), e = Eigen::VectorXd::Zero(mo);
  for (int j = 0; j < m; ++j) U(j, j) = R(j, j) = 1;
  for (int i = 0; i < k; ++i) {
    const int j = split[static_cast<std::size_t>(i)];
    if (std::isfinite(upper(j))) {
      U(j, j) = R(j, j) = -1;
      offset(j) = upper(j);
      E(j, m + i) = 1;       // + z_j in v_j's row
      E(m + i, j) = -1;      // (h_j − l_j) − v_j
      e(m + i) = upper(j) - lower(j);
    } else {
      U(j, m + i) = -1;  // u_j = v_j − z_j
      R(m + i, j) = -1;  // 0 ≤ z_j ⊥ −F_j ≥ 0
    }
  }
  const Eigen::MatrixXd A(lcs.A), B(lcs.B), C(lcs.C), D(lcs.D);
  OrthantLcs out;
  out.lcs = Lcs::Dense(A, B * U, R * C, R * D * U + E, lcs.p + B * offset,
                       R * (lcs.q + D * offset) + e);
  out.q_source_map = R;
  out.u_map = U;
  out.u_offset = offset;
  return out;
}

std::vector<ZooModel> ZooModels() {
  return {HalfWaveRectifier(),  BridgeRectifier(),  RlcDiode(),
          BuckConverter(),      BuckConverterAutonomous(),
          BoostConverter(),     RelayPlain(),       RelaySliding(),       RelayChattering(),
          TwistingController(), FilippovSpiral(),   ColpittsOscillator(), ResonantInverter()};
}

ZooModel ZooModelNamed(const std::string& key) {
  for (ZooModel& model : ZooModels()) {
    if (model.key == key) return std::move(model);
  }
  throw std::invalid_argument("no zoo model named \"" + key + "\"");
}

Eigen::VectorXd StateErrorsAfterJump(const ZooModel& model, const Trajectory& run) {
  const auto reference = model.reference();
  Eigen::VectorXd range = Eigen::VectorXd::Zero(model.n());
  constexpr int kRangeTimes = 1001;
  for (int k = 0; k < kRangeTimes; ++k)
    range = range.cwiseMax(reference.X(model.horizon * k / (kRangeTimes - 1)).cwiseAbs());
  Eigen::VectorXd worst = Eigen::VectorXd::Zero(model.n());
  for (std::size_t k = 1; k < run.times.size(); ++k)
    worst = worst.cwiseMax(
        ((run.states[k] - reference.X(run.times[k])).cwiseAbs().array() / range.array()).matrix());
  return worst;
}

double ErrorAfterJump(const ZooModel& model, const Trajectory& run) {
  return StateErrorsAfterJump(model, run).maxCoeff();
}

}  // namespace dvi::zoo
