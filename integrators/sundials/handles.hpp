// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

namespace dvi::internal {

/// Owning handles for the SUNDIALS objects every run needs, whichever
/// integrator (CVODE or IDA) it drives; freed in reverse order of creation by
/// the members' declaration order at the use site. Not copyable: each owns a
/// C pointer. SUNDIALS reports allocation failure by a null pointer or a
/// nonzero flag; the constructors throw std::bad_alloc for both.

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

}  // namespace dvi::internal
