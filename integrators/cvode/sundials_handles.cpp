// SPDX-License-Identifier: Apache-2.0
#include "sundials_handles.hpp"

#include <new>

#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace dvi::internal {

// SUNDIALS reports allocation failure by a null pointer or a nonzero flag;
// both are out of memory, which C++ spells std::bad_alloc.

SunContext::SunContext() {
  if (SUNContext_Create(nullptr, &context_) != 0 || context_ == nullptr) throw std::bad_alloc();
}

SunContext::~SunContext() { SUNContext_Free(&context_); }

SerialVector::SerialVector(long length, SUNContext context)
    : vector_(N_VNew_Serial(length, context)) {
  if (vector_ == nullptr) throw std::bad_alloc();
}

SerialVector::~SerialVector() { N_VDestroy(vector_); }

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

CvodeMemory::CvodeMemory(int linear_multistep, SUNContext context)
    : memory_(CVodeCreate(linear_multistep, context)) {
  if (memory_ == nullptr) throw std::bad_alloc();
}

CvodeMemory::~CvodeMemory() { CVodeFree(&memory_); }

}  // namespace dvi::internal
