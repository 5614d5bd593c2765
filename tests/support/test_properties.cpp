// SPDX-License-Identifier: Apache-2.0
#include "support/test_properties.hpp"

#include <iomanip>
#include <sstream>

namespace dvi::testing {

std::string Scientific(double value) {
  std::ostringstream text;
  text << std::scientific << std::setprecision(3) << value;
  return text.str();
}

}  // namespace dvi::testing
