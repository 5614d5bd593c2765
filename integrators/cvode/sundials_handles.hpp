// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdlib>
#include <exception>
#include <string>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

namespace dvi::internal {

/// The text of a return flag from CVodeGetReturnFlagName or
/// IDAGetReturnFlagName, which malloc it for the caller to free.
inline std::string FlagName(char* name) {
  std::string text = name != nullptr ? name : "an unknown flag";
  std::free(name);
  return text;
}

/// Runs the body of a SUNDIALS callback. Exceptions must not cross
/// SUNDIALS' C frames: one is stored in `error`, for the caller to rethrow
/// once the solver returns, and the callback reports -1 (unrecoverable).
template <typename Body>
int GuardedCallback(std::exception_ptr& error, Body&& body) {
  try {
    return body();
  } catch (...) {
    error = std::current_exception();
    return -1;
  }
}

/// Owning handles for the SUNDIALS objects of one CVODE run, freed in reverse
/// order of creation by the members' declaration order at the use site.
/// Not copyable: each owns a C pointer.

class SunContext {
 public:
  SunContext();
  ~SunContext();
  SunContext(const SunContext&) = delete;
  SunContext& operator=(const SunContext&) = delete;
  SUNContext get() const { return context_; }

 private:
  SUNContext context_ = nullptr;
};

class SerialVector {
 public:
  SerialVector(long length, SUNContext context);
  ~SerialVector();
  SerialVector(const SerialVector&) = delete;
  SerialVector& operator=(const SerialVector&) = delete;
  N_Vector get() const { return vector_; }
  double* data() const { return N_VGetArrayPointer(vector_); }

 private:
  N_Vector vector_ = nullptr;
};

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

class CvodeMemory {
 public:
  CvodeMemory(int linear_multistep, SUNContext context);
  ~CvodeMemory();
  CvodeMemory(const CvodeMemory&) = delete;
  CvodeMemory& operator=(const CvodeMemory&) = delete;
  void* get() const { return memory_; }

 private:
  void* memory_ = nullptr;
};

}  // namespace dvi::internal
