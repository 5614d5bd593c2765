// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "dvi/adapters/index_one_rhs.hpp"

namespace dvi::internal {

/// For the C callbacks of cvode_rhs.hpp, which cannot let an exception cross
/// CVODE's frames: they record its text as the rhs's message(). Private to
/// the library, so that a user of IndexOneRhs cannot set it.
struct IndexOneRhsAccess {
  static void SetMessage(IndexOneRhs& rhs, std::string message);
};

}  // namespace dvi::internal
