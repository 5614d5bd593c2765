// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "dvi/observer.hpp"

namespace dvi::testing {

/// What a test's observer saw, by value.
struct Seen {
  double t;
  Eigen::VectorXd x, u;
  ObservationPoint point;
};

/// An observer that appends each observation to `seen` and goes on, or
/// stops the run at the first state whose x(0) is below `stop_below`.
inline Observer Recorder(std::vector<Seen>& seen, double stop_below = -INFINITY) {
  return [&seen, stop_below](const Observation& observation) {
    seen.push_back({observation.t, observation.x, observation.u, observation.point});
    return observation.x(0) < stop_below ? ObserverReply::kStop : ObserverReply::kContinue;
  };
}

}  // namespace dvi::testing
