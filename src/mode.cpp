// SPDX-License-Identifier: Apache-2.0
#include "dvi/mode.hpp"

namespace dvi {

std::string ModeLetters(const Mode& mode) {
  std::string text;
  for (const MultiplierBound bound : mode)
    text += bound == MultiplierBound::kFree ? 'f' : bound == MultiplierBound::kLower ? 'l' : 'u';
  return text;
}

std::string_view ToString(MultiplierBound bound) {
  switch (bound) {
    case MultiplierBound::kFree: return "free";
    case MultiplierBound::kLower: return "lower";
    case MultiplierBound::kUpper: return "upper";
  }
  return "unknown";
}

}  // namespace dvi
