// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "dvi/error.hpp"

namespace dvi::testing {

/// Expects run() to throw InvalidInputError whose message contains name.
inline void ExpectThrowNaming(const std::function<void()>& run, const std::string& name) {
  try {
    run();
    ADD_FAILURE() << "no InvalidInputError; expected one naming " << name;
  } catch (const InvalidInputError& error) {
    EXPECT_NE(std::string(error.what()).find(name), std::string::npos)
        << "message \"" << error.what() << "\" does not name " << name;
  }
}

}  // namespace dvi::testing
