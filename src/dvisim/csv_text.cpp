// SPDX-License-Identifier: Apache-2.0
#include "csv_text.hpp"

#include <charconv>

namespace dvi::dvisim {

// std::to_chars with a precision writes what printf("%.17g") writes in the
// C locale ([charconv.to.chars]), by Ryu rather than glibc's multi-precision
// __printf_fp: trajectory.csv of the diode bridge's 2001 rows cost 45M
// instructions by snprintf, 1.5 times the integration (issue 31).
std::string ExactNumber(double value) {
  char text[32];
  const std::to_chars_result end =
      std::to_chars(text, text + sizeof(text), value, std::chars_format::general, 17);
  return std::string(text, end.ptr);
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace dvi::dvisim
