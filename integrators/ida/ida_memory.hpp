// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <sundials/sundials_context.h>

namespace dvi::internal {

/// Owns IDA's memory block (sundials/handles.hpp's rules).
class IdaMemory {
 public:
  explicit IdaMemory(SUNContext context);
  ~IdaMemory();
  IdaMemory(const IdaMemory&) = delete;
  IdaMemory& operator=(const IdaMemory&) = delete;
  void* get() const { return memory_; }

 private:
  void* memory_ = nullptr;
};

}  // namespace dvi::internal
