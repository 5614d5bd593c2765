// SPDX-License-Identifier: Apache-2.0
#include "sundials/linear_solvers.hpp"

#include <new>

#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

namespace dvi::internal {

DenseLinearSolver::DenseLinearSolver(N_Vector template_vector, long n, SUNContext context)
    : matrix_(SUNDenseMatrix(n, n, context)) {
  if (matrix_ == nullptr) throw std::bad_alloc();
  solver_ = SUNLinSol_Dense(template_vector, matrix_, context);
  if (solver_ == nullptr) {
    SUNMatDestroy(matrix_);
    throw std::bad_alloc();
  }
}

DenseLinearSolver::~DenseLinearSolver() {
  SUNLinSolFree(solver_);
  SUNMatDestroy(matrix_);
}

KluLinearSolver::KluLinearSolver(N_Vector template_vector, long n, long nonzeros,
                                 SUNContext context)
    : matrix_(SUNSparseMatrix(n, n, nonzeros, CSC_MAT, context)) {
  if (matrix_ == nullptr) throw std::bad_alloc();
  solver_ = SUNLinSol_KLU(template_vector, matrix_, context);
  if (solver_ == nullptr) {
    SUNMatDestroy(matrix_);
    throw std::bad_alloc();
  }
}

KluLinearSolver::~KluLinearSolver() {
  SUNLinSolFree(solver_);
  SUNMatDestroy(matrix_);
}

bool KluLinearSolver::Reset(long nonzeros) {
  return SUNLinSol_KLUReInit(solver_, matrix_, nonzeros, SUNKLU_REINIT_FULL) == 0;
}

}  // namespace dvi::internal
