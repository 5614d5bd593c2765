// SPDX-License-Identifier: Apache-2.0
#include "cvode/cvode_memory.hpp"

#include <new>

#include <cvode/cvode.h>

namespace dvi::internal {

CvodeMemory::CvodeMemory(int linear_multistep, SUNContext context)
    : memory_(CVodeCreate(linear_multistep, context)) {
  if (memory_ == nullptr) throw std::bad_alloc();
}

CvodeMemory::~CvodeMemory() { CVodeFree(&memory_); }

void CvodeMemory::Recreate(int linear_multistep, SUNContext context) {
  void* memory = CVodeCreate(linear_multistep, context);
  if (memory == nullptr) throw std::bad_alloc();
  CVodeFree(&memory_);
  memory_ = memory;
}

}  // namespace dvi::internal
