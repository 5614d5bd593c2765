// SPDX-License-Identifier: Apache-2.0
#include "ida/ida_memory.hpp"

#include <new>

#include <ida/ida.h>

namespace dvi::internal {

IdaMemory::IdaMemory(SUNContext context) : memory_(IDACreate(context)) {
  if (memory_ == nullptr) throw std::bad_alloc();
}

IdaMemory::~IdaMemory() { IDAFree(&memory_); }

}  // namespace dvi::internal
