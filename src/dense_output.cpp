// SPDX-License-Identifier: Apache-2.0
#include "dvi/dense_output.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "check.hpp"

namespace dvi {
namespace {

// Round-off slack of a step's start, t_n − h, against the previous end.
double Slack(double t, double h) {
  return 64 * std::numeric_limits<double>::epsilon() * (std::abs(t) + std::abs(h));
}

}  // namespace

double DenseOutput::begin() const { return empty() ? NAN : pieces_.front().begin; }

double DenseOutput::end() const { return empty() ? NAN : pieces_.back().end; }

void DenseOutput::Append(double begin, double end, double t_n, double h,
                         const Eigen::Ref<const Eigen::MatrixXd>& c) {
  DVI_THROW_UNLESS(h > 0 && std::isfinite(t_n) && std::isfinite(h) && begin < end &&
                       begin >= t_n - h - Slack(t_n, h) && end <= t_n + Slack(t_n, h),
                   "DenseOutput::Append: [" << begin << ", " << end << "] is not within the step ("
                                            << t_n - h << ", " << t_n << "]");
  DVI_THROW_UNLESS(c.cols() >= 1 && c.allFinite(),
                   "DenseOutput::Append: the step ending at t = " << t_n
                                                                  << " has no finite coefficients");
  if (empty()) dim_ = c.rows();
  DVI_THROW_UNLESS(c.rows() == dim_, "DenseOutput::Append: the step ending at t = "
                                         << t_n << " has " << c.rows() << " components, expected "
                                         << dim_);
  DVI_THROW_UNLESS(empty() || begin >= this->end() - Slack(begin, end - begin),
                   "DenseOutput::Append: the piece [" << begin << ", " << end
                                                      << "] starts before the last one ends at "
                                                      << this->end());
  pieces_.push_back({begin, end, t_n, h, static_cast<int>(c.cols()) - 1, values_.size()});
  values_.insert(values_.end(), c.data(), c.data() + c.size());
}

void DenseOutput::Append(const DenseOutput& later) {
  for (const Piece& piece : later.pieces_) {
    const Eigen::Map<const Eigen::MatrixXd> c(later.values_.data() + piece.offset, later.dim_,
                                              piece.degree + 1);
    Append(piece.begin, piece.end, piece.t_n, piece.h, c);
  }
}

void DenseOutput::TruncateAfter(double t) {
  while (!pieces_.empty() && pieces_.back().begin >= t) {
    values_.resize(pieces_.back().offset);
    pieces_.pop_back();
  }
  if (!pieces_.empty() && pieces_.back().end > t) pieces_.back().end = t;
  if (pieces_.empty()) dim_ = 0;
}

const DenseOutput::Piece* DenseOutput::Find(double t) const {
  if (empty() || !(t >= begin() - Slack(begin(), 0)) || !(t <= end())) return nullptr;
  // The first piece ending at or after t; its start must reach back to t.
  const auto piece = std::lower_bound(pieces_.begin(), pieces_.end(), t,
                                      [](const Piece& p, double time) { return p.end < time; });
  if (piece == pieces_.end() || t < piece->begin - Slack(piece->begin, piece->end - piece->begin))
    return nullptr;
  return &*piece;
}

bool DenseOutput::Covers(double t) const { return Find(t) != nullptr; }

const DenseOutput::Piece& DenseOutput::Covering(double t) const {
  const Piece* piece = Find(t);
  DVI_THROW_UNLESS(piece, "DenseOutput: no step covers t = " << t << " (the output spans ["
                                                             << begin() << ", " << end() << "])");
  return *piece;
}

Eigen::VectorXd DenseOutput::Evaluate(const Piece& piece, double t) const {
  const Eigen::Map<const Eigen::MatrixXd> c(values_.data() + piece.offset, dim_, piece.degree + 1);
  const double s = (t - piece.t_n) / piece.h;
  Eigen::VectorXd x = c.col(piece.degree);  // Horner
  for (int k = piece.degree - 1; k >= 0; --k) x = c.col(k) + s * x;
  return x;
}

Eigen::VectorXd DenseOutput::State(double t) const { return Evaluate(Covering(t), t); }

Eigen::VectorXd DenseOutput::PieceChange(double t) const {
  const Piece& piece = Covering(t);
  return Evaluate(piece, piece.end) - Evaluate(piece, piece.begin);
}

Eigen::VectorXd DenseOutput::Derivative(double t) const {
  const Piece& piece = Covering(t);
  const Eigen::Map<const Eigen::MatrixXd> c(values_.data() + piece.offset, dim_, piece.degree + 1);
  const double s = (t - piece.t_n) / piece.h;
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(dim_);
  for (int k = piece.degree; k >= 1; --k) dx = k * c.col(k) + s * dx;
  return dx / piece.h;
}

std::string_view ToString(DenseOutputPolicy policy) {
  switch (policy) {
    case DenseOutputPolicy::kAuto: return "auto";
    case DenseOutputPolicy::kAlways: return "always";
    case DenseOutputPolicy::kNever: return "never";
  }
  return "unknown";
}

}  // namespace dvi
