// SPDX-License-Identifier: Apache-2.0
#include "number_text.hpp"

#include <charconv>

namespace dvi::internal {

void AppendNumber(std::string& text, double value) {
  // "%g" is "%.6g"; 32 characters hold any double's (-1.23457e-308, nan).
  char buffer[32];
  char* end =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 6).ptr;
  text.append(buffer, end);
}

std::string NumberText(double value) {
  std::string text;
  AppendNumber(text, value);
  return text;
}

}  // namespace dvi::internal
