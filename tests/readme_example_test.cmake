# SPDX-License-Identifier: Apache-2.0
# README's C++ block must be examples/quick_start.cpp's main(), which CTest
# builds and runs (example.quick_start): so the README's example cannot rot.
# Usage: cmake -DREADME=... -DEXAMPLE=... -P readme_example_test.cmake
file(READ "${README}" readme)
file(READ "${EXAMPLE}" example)
string(FIND "${readme}" "```cpp\n" open)
if(open EQUAL -1)
  message(FATAL_ERROR "${README}: no ```cpp block")
endif()
math(EXPR start "${open} + 7")
string(SUBSTRING "${readme}" ${start} -1 rest)
string(FIND "${rest}" "```" close)
string(SUBSTRING "${rest}" 0 ${close} block)
string(FIND "${example}" "int main() {" main)
if(main EQUAL -1)
  message(FATAL_ERROR "${EXAMPLE}: no int main() {")
endif()
string(SUBSTRING "${example}" ${main} -1 program)
if(NOT block STREQUAL program)
  message(FATAL_ERROR "README's C++ example differs from ${EXAMPLE}'s main(): copy it over")
endif()
