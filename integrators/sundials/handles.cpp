// SPDX-License-Identifier: Apache-2.0
#include "sundials/handles.hpp"

#include <new>

#include "sundials/linear_sum.hpp"

namespace dvi::internal {

SunContext::SunContext() {
  if (SUNContext_Create(nullptr, &context_) != 0 || context_ == nullptr) throw std::bad_alloc();
}

SunContext::~SunContext() { SUNContext_Free(&context_); }

SerialVector::SerialVector(long length, SUNContext context)
    : vector_(N_VNew_Serial(length, context)) {
  if (vector_ == nullptr) throw std::bad_alloc();
  UseSerialLinearSum(vector_);
}

SerialVector::~SerialVector() { N_VDestroy(vector_); }

}  // namespace dvi::internal
