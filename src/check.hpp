// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <sstream>
#include <string>

#include "dvi/error.hpp"

/// Throws dvi::InvalidInputError with the streamed message when cond is false.
/// For caller mistakes only (sizes, NaN, invalid options); numerical outcomes
/// go through a result's status. Usage: DVI_THROW_UNLESS(a.size() == n, "q has " << a.size() << " entries, expected " << n);
#define DVI_THROW_UNLESS(cond, message)             \
  do {                                              \
    if (!(cond)) {                                  \
      std::ostringstream dvi_throw_stream_;         \
      dvi_throw_stream_ << message;                 \
      throw ::dvi::InvalidInputError(dvi_throw_stream_.str()); \
    }                                               \
  } while (false)
