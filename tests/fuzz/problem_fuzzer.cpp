// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the static-problem reader of `dvisim solve`. Any input
// is read as a problem file; the contract is a ProblemFile or an InputError,
// nothing else.
#include <cstddef>
#include <cstdint>
#include <string>

#include "problem_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    dvi::dvisim::ParseProblemFile(text);
  } catch (const dvi::dvisim::InputError&) {
    // Bad input, answered with a message: the contract.
  }
  return 0;
}
