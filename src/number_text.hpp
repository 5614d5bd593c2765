// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

namespace dvi::internal {

/// Appends value as an ostream prints it by default ("%g": six significant
/// digits), by std::to_chars: no stream to set up and no locale, a fifth of
/// the instructions. For text formed on every run (the certificate's basis,
/// the start's reason), where a stream's set-up cost more than the run's
/// last steps.
void AppendNumber(std::string& text, double value);

/// value as AppendNumber writes it.
std::string NumberText(double value);

}  // namespace dvi::internal
