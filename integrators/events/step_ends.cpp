// SPDX-License-Identifier: Apache-2.0
#include "events/step_ends.hpp"

#include <limits>

#include "modes/step_interpolant.hpp"

namespace dvi::internal {

bool StepEnds::Begin(double t_n, double h) {
  // The integrator's t_n − h is the last step's end up to rounding.
  const bool start_known =
      std::abs(end_time_ - (t_n - h)) <= 4 * std::numeric_limits<double>::epsilon() * (std::abs(t_n) + h);
  start_roots_.swap(end_roots_);
  start_rates_.swap(end_rates_);
  start_rates_known_ = start_known && end_rates_known_;
  end_rates_known_ = false;
  end_time_ = NAN;
  return start_known;
}

void StepEnds::Moves(const Eigen::Ref<const Eigen::VectorXd>& x_n,
                     const Eigen::Ref<const Eigen::VectorXd>& rate_n, double h, double margin,
                     Eigen::VectorXd& moves) const {
  HermiteMoves(end_x_, end_rate_, x_n, rate_n, h, margin, moves);
}

void StepEnds::Rates(const Eigen::Ref<const Eigen::VectorXd>& x_n,
                     const Eigen::Ref<const Eigen::VectorXd>& rate_n, double h, double margin,
                     Eigen::VectorXd& rates) const {
  HermiteRates(end_x_, end_rate_, x_n, rate_n, h, margin, rates);
}

void StepEnds::End(double t_n, const Eigen::Ref<const Eigen::VectorXd>& x,
                   const Eigen::Ref<const Eigen::VectorXd>& rate) {
  end_x_ = x;
  end_rate_ = rate;
  end_time_ = t_n;
}

}  // namespace dvi::internal
