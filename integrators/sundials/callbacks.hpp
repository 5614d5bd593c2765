// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdlib>
#include <exception>
#include <string>

namespace dvi::internal {

/// The contract of every callback dvi hands to CVODE or IDA (right-hand
/// side, residual, Jacobian, roots, projection): exceptions must not cross
/// SUNDIALS' C frames. One is stored in `error`, for the caller to rethrow
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

/// The text of a return flag from CVodeGetReturnFlagName or
/// IDAGetReturnFlagName, which malloc it for the caller to free.
inline std::string FlagName(char* name) {
  std::string text = name != nullptr ? name : "an unknown flag";
  std::free(name);
  return text;
}

}  // namespace dvi::internal
