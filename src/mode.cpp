// SPDX-License-Identifier: Apache-2.0
#include "dvi/mode.hpp"

namespace dvi {

std::string ModeLetters(const Mode& mode) {
  std::string text;
  for (const MultiplierBound bound : mode)
    text += bound == MultiplierBound::kFree ? 'f' : bound == MultiplierBound::kLower ? 'l' : 'u';
  return text;
}

}  // namespace dvi
