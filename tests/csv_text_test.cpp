// SPDX-License-Identifier: Apache-2.0
// dvisim's CSV numbers: ExactNumber writes what printf("%.17g") writes (the
// format trajectory.csv has always had) and reads back the same double.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "csv_text.hpp"

namespace dvi::dvisim {
namespace {

std::string Printf17g(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

std::vector<double> EdgeValues() {
  using limits = std::numeric_limits<double>;
  return {0.0,          -0.0,           1.0,          -1.0,           0.1,
          1.0 / 3.0,    1e-300,         -2.5e300,     123456789012345678.0,
          1e16,         1e17,           9.999999999999999e16,         1e-5,
          1e-4,         limits::min(),  limits::denorm_min(),         limits::max(),
          limits::lowest(), limits::epsilon(), limits::infinity(), -limits::infinity(),
          limits::quiet_NaN()};
}

TEST(ExactNumber, WritesWhatPrintfPercent17gWrites) {
  for (const double value : EdgeValues()) EXPECT_EQ(ExactNumber(value), Printf17g(value)) << value;
  // Random bit patterns cover every exponent and the mantissas' last digits.
  std::mt19937_64 random(31);
  for (int k = 0; k < 100000; ++k) {
    const std::uint64_t bits = random();
    double value;
    std::memcpy(&value, &bits, sizeof(value));
    if (std::isnan(value)) continue;  // printf's sign of a NaN payload is glibc's own
    ASSERT_EQ(ExactNumber(value), Printf17g(value)) << "bits " << bits;
  }
}

TEST(ExactNumber, ReadsBackTheSameDouble) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> exponent(-300, 300);
  for (int k = 0; k < 10000; ++k) {
    const double value = std::pow(10.0, exponent(random)) * (k % 2 ? -1 : 1);
    EXPECT_EQ(std::strtod(ExactNumber(value).c_str(), nullptr), value);
  }
}

}  // namespace
}  // namespace dvi::dvisim
