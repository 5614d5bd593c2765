// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

namespace dvi::dvisim {

/// Owns: how dvisim writes numbers and text into its CSV files.

/// Enough digits (%.17g) to read back the same double.
std::string ExactNumber(double value);

/// A CSV field (RFC 4180): quoted, with quotes doubled, when it holds a
/// comma, a quote or a line break; as is otherwise.
std::string CsvField(const std::string& text);

}  // namespace dvi::dvisim
