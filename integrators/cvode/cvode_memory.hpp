// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <sundials/sundials_context.h>

namespace dvi::internal {

/// Owns CVODE's memory block (sundials/handles.hpp's rules).
class CvodeMemory {
 public:
  CvodeMemory(int linear_multistep, SUNContext context);
  ~CvodeMemory();
  CvodeMemory(const CvodeMemory&) = delete;
  CvodeMemory& operator=(const CvodeMemory&) = delete;
  void* get() const { return memory_; }
  /// A new block of another family (CVODE cannot change it in place), before
  /// CVodeInit.
  void Recreate(int linear_multistep, SUNContext context);

 private:
  void* memory_ = nullptr;
};

}  // namespace dvi::internal
