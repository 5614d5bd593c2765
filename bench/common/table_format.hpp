// SPDX-License-Identifier: Apache-2.0
// Numbers in the benchmarks' markdown tables.
#pragma once

#include <string>

namespace dvi::bench {

/// `value` by the printf `format`, or `missing` for NaN (a run that was
/// skipped or failed).
std::string Fmt(const char* format, double value, const char* missing = "–");

}  // namespace dvi::bench
