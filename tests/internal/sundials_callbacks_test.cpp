// SPDX-License-Identifier: Apache-2.0
// sundials/callbacks: the contract of every callback handed to CVODE or IDA.
#include <exception>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "sundials/callbacks.hpp"

namespace dvi::internal {
namespace {

TEST(GuardedCallback, PassesTheBodysFlagThrough) {
  std::exception_ptr error;
  EXPECT_EQ(GuardedCallback(error, [] { return 1; }), 1);  // recoverable, SUNDIALS' meaning
  EXPECT_EQ(error, nullptr);
}

TEST(GuardedCallback, StoresAnExceptionAndReportsUnrecoverable) {
  std::exception_ptr error;
  const int flag = GuardedCallback(error, []() -> int { throw std::runtime_error("f failed"); });
  EXPECT_EQ(flag, -1);
  ASSERT_NE(error, nullptr);
  try {
    std::rethrow_exception(error);
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "f failed");
  }
}

}  // namespace
}  // namespace dvi::internal
