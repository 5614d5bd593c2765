// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

namespace dvi::internal {

/// The linear solvers CVODE's and IDA's Newton iterations use, each a matrix
/// with its solver, owned together (handles.hpp's rules).

/// A dense n×n SUNMatrix with SUNLinSol_Dense on it.
class DenseLinearSolver {
 public:
  DenseLinearSolver(N_Vector template_vector, long n, SUNContext context);
  ~DenseLinearSolver();
  DenseLinearSolver(const DenseLinearSolver&) = delete;
  DenseLinearSolver& operator=(const DenseLinearSolver&) = delete;
  SUNMatrix matrix() const { return matrix_; }
  SUNLinearSolver solver() const { return solver_; }

 private:
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver solver_ = nullptr;
};

/// An n×n compressed-column SUNMatrix with SUNLinSol_KLU on it. Reset()
/// resizes the storage to a new pattern's nonzeros and drops KLU's symbolic
/// analysis (SUNLinSol_KLUReInit), which is otherwise reused by every
/// factorization while the pattern stays.
class KluLinearSolver {
 public:
  KluLinearSolver(N_Vector template_vector, long n, long nonzeros, SUNContext context);
  ~KluLinearSolver();
  KluLinearSolver(const KluLinearSolver&) = delete;
  KluLinearSolver& operator=(const KluLinearSolver&) = delete;
  SUNMatrix matrix() const { return matrix_; }
  SUNLinearSolver solver() const { return solver_; }
  /// @returns false when the storage cannot be reallocated.
  bool Reset(long nonzeros);

 private:
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver solver_ = nullptr;
};

}  // namespace dvi::internal
