// SPDX-License-Identifier: Apache-2.0
#include "support/random_problems.hpp"

#include <vector>

namespace dvi::test {

Eigen::VectorXd RandomVector(int m, std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> uniform(lo, hi);
  Eigen::VectorXd v(m);
  for (int i = 0; i < m; ++i) v(i) = uniform(rng);
  return v;
}

static Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd A(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) A(i, j) = uniform(rng);
  return A;
}

Eigen::MatrixXd RandomPMatrix(int m, std::mt19937& rng) {
  const Eigen::MatrixXd S = RandomMatrix(m, m, rng);
  const Eigen::MatrixXd N = RandomMatrix(m, m, rng);
  const Eigen::MatrixXd skew = N - N.transpose();
  return S * S.transpose() / m + skew + 0.1 * Eigen::MatrixXd::Identity(m, m);
}

Eigen::MatrixXd RandomTriangularPMatrix(int m, std::mt19937& rng) {
  std::uniform_real_distribution<double> positive(0.5, 2.0);
  Eigen::MatrixXd N = RandomMatrix(m, m, rng);
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(m, m);
  T.triangularView<Eigen::StrictlyLower>() = (2.0 * N).triangularView<Eigen::StrictlyLower>();
  Eigen::VectorXd d1(m), d2(m);
  for (int i = 0; i < m; ++i) {
    d1(i) = positive(rng);
    d2(i) = positive(rng);
  }
  return d1.asDiagonal() * T * d2.asDiagonal();
}

Eigen::MatrixXd RandomPsdMatrix(int m, int rank, std::mt19937& rng, bool add_skew) {
  const Eigen::MatrixXd S = RandomMatrix(m, rank, rng);
  Eigen::MatrixXd M = S * S.transpose();
  if (add_skew) {
    const Eigen::MatrixXd N = RandomMatrix(m, m, rng);
    M += N - N.transpose();
  }
  return M;
}

Eigen::SparseMatrix<double> RandomSparseSpd(int m, int nnz_per_row, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_int_distribution<int> column(0, m - 1);
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(m);
  for (int i = 0; i < m; ++i) {
    for (int k = 0; k < nnz_per_row / 2; ++k) {
      const int j = column(rng);
      if (j == i) continue;
      const double v = uniform(rng);
      triplets.emplace_back(i, j, v);  // symmetric pair
      triplets.emplace_back(j, i, v);
      row_sum(i) += std::abs(v);
      row_sum(j) += std::abs(v);
    }
  }
  for (int i = 0; i < m; ++i) triplets.emplace_back(i, i, row_sum(i) + 1.0);
  Eigen::SparseMatrix<double> M(m, m);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

ComplementaryPair RandomComplementaryPair(int m, std::mt19937& rng, double degenerate_fraction) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> value(0.5, 2.0);
  ComplementaryPair pair{Eigen::VectorXd::Zero(m), Eigen::VectorXd::Zero(m)};
  for (int i = 0; i < m; ++i) {
    const double kind = unit(rng);
    if (kind < degenerate_fraction) continue;
    if (kind < degenerate_fraction + (1.0 - degenerate_fraction) / 2) {
      pair.z(i) = value(rng);
    } else {
      pair.w(i) = value(rng);
    }
  }
  return pair;
}

Eigen::SparseMatrix<double> RandomGridSpd(int k, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int m = k * k;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(5 * static_cast<std::size_t>(m));
  Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(m);
  auto couple = [&](int a, int b) {
    const double v = uniform(rng);
    triplets.emplace_back(a, b, v);
    triplets.emplace_back(b, a, v);
    row_sum(a) += std::abs(v);
    row_sum(b) += std::abs(v);
  };
  for (int r = 0; r < k; ++r) {
    for (int c = 0; c < k; ++c) {
      const int i = r * k + c;
      if (c + 1 < k) couple(i, i + 1);
      if (r + 1 < k) couple(i, i + k);
    }
  }
  for (int i = 0; i < m; ++i) triplets.emplace_back(i, i, row_sum(i) + 1.0);
  Eigen::SparseMatrix<double> M(m, m);
  M.setFromTriplets(triplets.begin(), triplets.end());
  M.makeCompressed();
  return M;
}

}  // namespace dvi::test
