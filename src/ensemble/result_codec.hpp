// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "dvi/ensemble.hpp"

namespace dvi::internal {

/// Owns: the byte form in which ensemble results travel between ranks.
/// Doubles are copied bit for bit (a gathered result equals the one its
/// rank computed, whatever the rank count), strings and vectors carry their
/// length. Both ends are the same build, so byte order and sizes agree.
void AppendResult(const EnsembleResult& result, std::string& bytes);

/// Reads the results AppendResult wrote one after another into `bytes`.
/// @throws std::runtime_error on a truncated or malformed buffer (a
/// transport defect, never user input).
std::vector<EnsembleResult> ReadResults(const std::string& bytes);

}  // namespace dvi::internal
