// SPDX-License-Identifier: Apache-2.0
#include "ida_handles.hpp"

#include <new>

#include <ida/ida.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

namespace dvi::internal {

// As in cvode/sundials_handles.cpp: a null pointer from a SUNDIALS
// constructor is an allocation failure.

IdaMemory::IdaMemory(SUNContext context) : memory_(IDACreate(context)) {
  if (memory_ == nullptr) throw std::bad_alloc();
}

IdaMemory::~IdaMemory() { IDAFree(&memory_); }

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
