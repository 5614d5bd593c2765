// SPDX-License-Identifier: Apache-2.0
#include "support/sampled_data_relay.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::testing {
namespace {

double Control(double v) { return v < SampledDataRelay::kReference ? 1.0 : -2.0; }

}  // namespace

Lcs SampledDataRelay::Problem() {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3);
  A(0, 1) = 1;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, 1), C = Eigen::MatrixXd::Zero(1, 3);
  B(0, 0) = 1;
  C(0, 0) = 1;
  return Lcs::Dense(A, B, C, Eigen::MatrixXd::Zero(1, 1),
                    (Eigen::VectorXd(3) << 0, 0, 1).finished());
}

UserEvents SampledDataRelay::Controller() {
  UserEvents events;
  events.g = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(2) - kPeriod);
  };
  events.events = {{EventDirection::kRising, UserEventAction::kModify}};
  events.modify = [](double, const Eigen::VectorXd& x, int) {
    return (Eigen::VectorXd(3) << x(0), Control(x(0)), 0.0).finished();
  };
  return events;
}

Eigen::VectorXd SampledDataRelay::Start() {
  return (Eigen::VectorXd(3) << 0.3, -2.0, 0.0).finished();
}

double SampledDataRelay::V(double t) {
  double v = 0.3, s = -2, start = 0;
  while (t > start + kPeriod) {
    v = std::max(0.0, v + s * kPeriod);
    s = Control(v);
    start += kPeriod;
  }
  return std::max(0.0, v + s * (t - start));
}

double SampledDataRelay::EventTimeError(const Trajectory& run) {
  double worst = 0;
  int k = 0;
  for (const Event& event : run.events)
    if (event.kind == EventKind::kUser)
      worst = std::max(worst, std::abs(event.time - ++k * kPeriod));
  return worst;
}

int SampledDataRelay::UserEventCount(const Trajectory& run) {
  return static_cast<int>(std::count_if(run.events.begin(), run.events.end(),
                                        [](const Event& e) { return e.kind == EventKind::kUser; }));
}

double SampledDataRelay::StateError(const Trajectory& run) {
  double worst = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    worst = std::max(worst, std::abs(run.states[k](0) - V(run.times[k])));
  return worst;
}

}  // namespace dvi::testing
