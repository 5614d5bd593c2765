// SPDX-License-Identifier: Apache-2.0
// ModeDaeRun's output: samples at the output times from IDA's interpolant, the dense output and the certificate's ODE defects.
#include "ida/mode_dae_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <ida/ida.h>

#include "certify.hpp"
#include "rounding_floor.hpp"

namespace dvi::internal {

void ModeDaeRun::Sample(double t, ObservationPoint point) {
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
  trajectory_.times.push_back(t);
  trajectory_.states.push_back(y.head(n_));
  trajectory_.multipliers.push_back(ConsistentMultiplier(y));
  observations_.Row(trajectory_.times.size() - 1, point, dae_.mode());
}

// IDA's u is algebraic and held by Newton only to about rtol |u| + atol:
// the mode's free rows w = C x + D u + q = 0 would then be off by |D| times
// that (the diode bridge at rtol 1e-6, atol 1e-8: 2.3e-8, past the VI
// certificate's 100 × solver tolerance). Outputs carry u solved from x by
// (5.8) instead, as CVODE's do: the mode's multiplier at the reported x.
// IDA's own where (5.8) is singular (MakeConsistent failed at the mode's
// entry already, so only a defensive fallback).
Eigen::VectorXd ModeDaeRun::ConsistentMultiplier(const Eigen::Ref<const Eigen::VectorXd>& y) {
  Eigen::VectorXd x = y.head(n_), u = y.tail(m_);
  std::string why;
  if (m_ == 0 || !dae_.MakeConsistent(x, u, why)) return y.tail(m_);
  return u;
}

// Requested times before `before` from IDA's interpolant of the last step
// (x and u alike: u is a smooth part of y inside a mode).
void ModeDaeRun::SampleOutputs(double before) {
  // The certificate's ODE defect at the sample nearest the step's middle.
  double t_n = 0, h = 0, middle = NAN, nearest = NAN;
  if (IDAGetCurrentTime(ida_.get(), &t_n) == IDA_SUCCESS &&
      IDAGetLastStep(ida_.get(), &h) == IDA_SUCCESS)
    middle = t_n - h / 2;
  const OutputSchedule::Range served =
      outputs_.Served(outputs_.TakeBefore(before), -std::numeric_limits<double>::infinity());
  for (auto time = served.begin; time != served.end; ++time) {
    const double t = *time;
    if (IDAGetDky(ida_.get(), t, 0, dky_.get()) != IDA_SUCCESS) continue;
    const Eigen::Map<const Eigen::VectorXd> y(dky_.data(), dae_.size());
    trajectory_.times.push_back(t);
    trajectory_.states.push_back(y.head(n_));
    trajectory_.multipliers.push_back(ConsistentMultiplier(y));
    observations_.Row(trajectory_.times.size() - 1, ObservationPoint::kOutputTime, dae_.mode());
    if (!(std::abs(t - middle) >= std::abs(nearest - middle))) nearest = t;
  }
  if (!std::isnan(nearest)) MeasureDefect(nearest);
}

// Certificate: the ODE's defect x' − (A x + B u + p) of IDA's interpolant
// at t within the last step, added to the run's certificate.
void ModeDaeRun::MeasureDefect(double t) {
  double h = 0;
  void* ida = ida_.get();
  if (IDAGetLastStep(ida, &h) != IDA_SUCCESS || !(h > 0)) return;
  const Eigen::Map<const Eigen::VectorXd> dky(dky_.data(), dae_.size());
  if (IDAGetDky(ida, t, 0, dky_.get()) != IDA_SUCCESS) return;
  mid_y_ = dky;
  if (IDAGetDky(ida, t, 1, dky_.get()) != IDA_SUCCESS) return;
  mid_yp_ = dky;
  const auto x = mid_y_.head(n_), u = mid_y_.tail(m_), rate = mid_yp_.head(n_);
  mid_f_ = lcs_.p;
  mid_f_.noalias() += lcs_.A * x;
  mid_f_.noalias() += lcs_.B * u;
  // The interpolant's derivative differences values of size |x| over the
  // step, f sums terms of its own size: a few ulps of each.
  mid_rounding_ = kRoundingUlps * std::numeric_limits<double>::epsilon() *
                  (h * (mid_f_.cwiseAbs() + rate.cwiseAbs()) + x.cwiseAbs());
  // IDA weighs the step's local error by y at its start, where it sets its
  // weights: |x| at t alone is ~0 where a component crosses zero there.
  mid_size_ = x.cwiseAbs();
  double t_n = 0;
  if (IDAGetCurrentTime(ida, &t_n) == IDA_SUCCESS &&
      IDAGetDky(ida, t_n - h, 0, dky_.get()) == IDA_SUCCESS)
    mid_size_ = mid_size_.cwiseMax(dky.head(n_).cwiseAbs());
  AddOdeDefect(t, h, rate, mid_f_, mid_size_, mid_rounding_, options_.rtol,
               Eigen::Map<const Eigen::VectorXd>(atol_.data(), n_),
                         trajectory_.certificate.ode);
}

// Where the dense output is kept: the last step's interpolant of x (and of
// u, InterpolatedMultipliers) over [its start, end] (end: the step's end,
// or the root that cut it short; its start no earlier than what is kept
// already), and its ODE defect at the midpoint (Certificate).
void ModeDaeRun::RecordStep(double end) {
  if (!KeepsDenseOutput(options_.dense_output, options_.output_times)) return;
  double t_n = 0, h = 0;
  int q = 0;
  void* ida = ida_.get();
  if (IDAGetCurrentTime(ida, &t_n) != IDA_SUCCESS || IDAGetLastStep(ida, &h) != IDA_SUCCESS ||
      IDAGetLastOrder(ida, &q) != IDA_SUCCESS || !(h > 0) || q < 1)
    return;
  const double begin = std::max(t_n - h, recorded_until_);
  if (!(end > begin)) return;
  const Eigen::Map<const Eigen::VectorXd> dky(dky_.data(), dae_.size());
  scaled_taylor_.resize(n_, q + 1);
  scaled_taylor_u_.resize(m_, q + 1);
  double scale = 1;  // h^k / k!
  for (int k = 0; k <= q; ++k) {
    if (k > 0) scale *= h / k;
    if (IDAGetDky(ida, t_n, k, dky_.get()) != IDA_SUCCESS) return;
    scaled_taylor_.col(k) = scale * dky.head(n_);
    scaled_taylor_u_.col(k) = scale * dky.tail(m_);
  }
  recorded_until_ = end;
  trajectory_.dense.Append(begin, end, t_n, h, scaled_taylor_);
  if (m_ > 0) multipliers_.Append(begin, end, t_n, h, scaled_taylor_u_);
  // The piece is output, so it is checked as the rows are.
  MeasureDefect(begin + (end - begin) / 2);
}

}  // namespace dvi::internal
