// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

namespace dvi::testing {

/// `value` in scientific notation with four significant digits
/// ("1.234e-09"): the measured figures tests record with RecordProperty
/// (errors, slopes, tolerances), where the exponent is what is read.
std::string Scientific(double value);

}  // namespace dvi::testing
