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
  const int n = lcs.n(), m = lcs.m();
  if (!lcs.K.IsBox()) throw std::invalid_argument("ToOrthant: K is not a box");
  const auto [lower, upper] = lcs.K.BoxBounds();
  std::vector<int> boxed;  // components with two finite bounds
  for (int j = 0; j < m; ++j) {
    if (std::isfinite(lower(j)) && std::isfinite(upper(j))) {
      boxed.push_back(j);
    } else if (!(lower(j) == 0 && upper(j) == HUGE_VAL)) {
      throw std::invalid_argument("ToOrthant: u" + std::to_string(j + 1) +
                                  " is neither in [0, ∞) nor in a finite interval");
    }
  }
  const int k = static_cast<int>(boxed.size()), mo = m + k;
  // u = S ũ + c on the first m components of the new u (S = diag(±1)), and
  // each box row of w flips sign (its pair is v_j ⊥ z_j − F_j).
  Eigen::VectorXd sign = Eigen::VectorXd::Ones(m), offset = Eigen::VectorXd::Zero(m);
  for (const int j : boxed) {
    sign(j) = -1;
    offset(j) = upper(j);
  }
  const Eigen::MatrixXd A(lcs.A), B(lcs.B), C(lcs.C), D(lcs.D);
  const Eigen::MatrixXd BS = B * sign.asDiagonal();
  Eigen::MatrixXd Bo = Eigen::MatrixXd::Zero(n, mo), Co = Eigen::MatrixXd::Zero(mo, n),
                  Do = Eigen::MatrixXd::Zero(mo, mo);
  Eigen::VectorXd po = lcs.p + B * offset, qo = Eigen::VectorXd::Zero(mo);
  Bo.leftCols(m) = BS;
  Co.topRows(m) = sign.asDiagonal() * C;
  Do.topLeftCorner(m, m) = sign.asDiagonal() * D * sign.asDiagonal();
  qo.head(m) = sign.asDiagonal() * (lcs.q + D * offset);
  for (int i = 0; i < k; ++i) {
    const int j = boxed[static_cast<std::size_t>(i)];
    Do(j, m + i) = 1;       // + z_j in v_j's row
    Do(m + i, j) = -1;      // (h_j − l_j) − v_j
    qo(m + i) = upper(j) - lower(j);
  }
  OrthantLcs out;
  out.lcs = Lcs::Dense(A, Bo, Co, Do, po, qo);
  out.q_source_map = Eigen::MatrixXd::Zero(mo, m);
  out.q_source_map.topRows(m) = sign.asDiagonal();
  out.u_map = Eigen::MatrixXd::Zero(m, mo);
  out.u_map.leftCols(m) = sign.asDiagonal();
  out.u_offset = offset;
  return out;
}

std::vector<ZooModel> ZooModels() {
  return {HalfWaveRectifier(),  BridgeRectifier(), RlcDiode(),
          BuckConverter(),      BuckConverterAutonomous(),
          BoostConverter(),     RelayPlain(),      RelaySliding(),     RelayChattering(),
          TwistingController(), FilippovSpiral(), ColpittsOscillator()};
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
