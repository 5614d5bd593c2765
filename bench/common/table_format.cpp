// SPDX-License-Identifier: Apache-2.0
#include "table_format.hpp"

#include <cmath>
#include <cstdio>

namespace dvi::bench {

std::string Fmt(const char* format, double value, const char* missing) {
  if (std::isnan(value)) return missing;
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace dvi::bench
