// SPDX-License-Identifier: Apache-2.0
#include "expression_canonical.hpp"

#include <algorithm>
#include <sstream>
#include <string>

namespace dvi::dvisim {
namespace {

// Kinds in a fixed order. What neither the parser nor differentiation
// makes (lists, relations, ...) shares the last rank, told apart by text.
constexpr int kProductRank = 4;
int Rank(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return 0;
  if (GiNaC::is_a<GiNaC::constant>(e)) return 1;
  if (GiNaC::is_a<GiNaC::symbol>(e)) return 2;
  if (GiNaC::is_a<GiNaC::power>(e)) return 3;
  if (GiNaC::is_a<GiNaC::mul>(e)) return kProductRank;
  if (GiNaC::is_a<GiNaC::add>(e)) return 5;
  if (GiNaC::is_a<GiNaC::function>(e)) return 6;
  return 7;
}

int Compare(const std::string& a, const std::string& b) { return a < b ? -1 : (b < a ? 1 : 0); }
int Compare(std::size_t a, std::size_t b) { return a < b ? -1 : (b < a ? 1 : 0); }

std::string Text(const GiNaC::ex& e) {
  std::ostringstream text;
  text << e;
  return text.str();
}

bool IsUnit(const GiNaC::ex& e) {
  return GiNaC::is_a<GiNaC::numeric>(e) && abs(GiNaC::ex_to<GiNaC::numeric>(e)).is_equal(1);
}

bool IsOddInteger(const GiNaC::ex& e) {
  return GiNaC::is_a<GiNaC::numeric>(e) && GiNaC::ex_to<GiNaC::numeric>(e).is_odd();
}

}  // namespace

const std::vector<GiNaC::ex>& CanonicalOrder::Operands(const GiNaC::ex& e) {
  const auto found = operands_.find(e);
  if (found != operands_.end()) return found->second;
  std::vector<GiNaC::ex> operands;
  operands.reserve(e.nops());
  for (std::size_t k = 0; k < e.nops(); ++k) operands.push_back(e.op(k));
  if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e))
    std::stable_sort(operands.begin(), operands.end(),
                     [this](const GiNaC::ex& a, const GiNaC::ex& b) {
                       const int by_magnitude = CompareMagnitude(a, b);
                       return by_magnitude != 0 ? by_magnitude < 0 : !Negative(a) && Negative(b);
                     });
  return operands_.emplace(e, std::move(operands)).first->second;
}

bool CanonicalOrder::Negative(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e).is_negative();
  const bool sum = GiNaC::is_a<GiNaC::add>(e), product = GiNaC::is_a<GiNaC::mul>(e);
  const bool odd_power = GiNaC::is_a<GiNaC::power>(e) && IsOddInteger(e.op(1));
  if (!sum && !product && !odd_power) return false;
  const auto found = negative_.find(e);
  if (found != negative_.end()) return found->second;
  bool negative = false;
  if (sum) {
    negative = Negative(Operands(e).front());
  } else if (product) {
    for (const GiNaC::ex& factor : Operands(e)) negative = negative != Negative(factor);
  } else {
    negative = Negative(e.op(0));
  }
  negative_.emplace(e, negative);
  return negative;
}

int CanonicalOrder::CompareSigned(const GiNaC::ex& a, const GiNaC::ex& b) {
  const bool negative_a = Negative(a), negative_b = Negative(b);
  if (negative_a != negative_b) return negative_a ? 1 : -1;
  return CompareMagnitude(a, b);
}

int CanonicalOrder::CompareMagnitude(const GiNaC::ex& a, const GiNaC::ex& b) {
  if (a.is_equal(b)) return 0;
  // A product's magnitude is that of its factors other than ±1, so −x1
  // (a product to GiNaC) is x1 again.
  const auto magnitude_factors = [this](const GiNaC::ex& e) {
    std::vector<GiNaC::ex> factors;
    if (!GiNaC::is_a<GiNaC::mul>(e)) return std::vector<GiNaC::ex>{e};
    for (const GiNaC::ex& factor : Operands(e))
      if (!IsUnit(factor)) factors.push_back(factor);
    return factors;
  };
  const std::vector<GiNaC::ex> factors_a = magnitude_factors(a), factors_b = magnitude_factors(b);
  if (factors_a.size() != 1 || factors_b.size() != 1) {
    const int rank_a = factors_a.size() == 1 ? Rank(factors_a[0]) : kProductRank;
    const int rank_b = factors_b.size() == 1 ? Rank(factors_b[0]) : kProductRank;
    if (rank_a != rank_b) return rank_a - rank_b;
    if (const int by_count = Compare(factors_a.size(), factors_b.size()); by_count != 0)
      return by_count;
    for (std::size_t k = 0; k < factors_a.size(); ++k)
      if (const int c = CompareMagnitude(factors_a[k], factors_b[k]); c != 0) return c;
    return 0;
  }
  const GiNaC::ex& x = factors_a[0];
  const GiNaC::ex& y = factors_b[0];
  if (const int by_rank = Rank(x) - Rank(y); by_rank != 0) return by_rank;
  if (GiNaC::is_a<GiNaC::numeric>(x))  // by exact value, never by hash
    return abs(GiNaC::ex_to<GiNaC::numeric>(x)).compare(abs(GiNaC::ex_to<GiNaC::numeric>(y)));
  if (GiNaC::is_a<GiNaC::symbol>(x))
    return Compare(GiNaC::ex_to<GiNaC::symbol>(x).get_name(),
                   GiNaC::ex_to<GiNaC::symbol>(y).get_name());
  if (GiNaC::is_a<GiNaC::add>(x)) {
    // Terms by magnitude, then each term's sign relative to the first.
    const std::vector<GiNaC::ex>& terms_x = Operands(x);
    const std::vector<GiNaC::ex>& terms_y = Operands(y);
    if (const int by_count = Compare(terms_x.size(), terms_y.size()); by_count != 0)
      return by_count;
    for (std::size_t k = 0; k < terms_x.size(); ++k)
      if (const int c = CompareMagnitude(terms_x[k], terms_y[k]); c != 0) return c;
    for (std::size_t k = 1; k < terms_x.size(); ++k) {
      const bool flip_x = Negative(terms_x[k]) != Negative(terms_x[0]);
      const bool flip_y = Negative(terms_y[k]) != Negative(terms_y[0]);
      if (flip_x != flip_y) return flip_x ? 1 : -1;
    }
    return 0;
  }
  if (GiNaC::is_a<GiNaC::power>(x)) {
    // An integer power's sign is a factor outside; any other's base is read
    // with its sign.
    if (const int by_exponent = CompareSigned(x.op(1), y.op(1)); by_exponent != 0)
      return by_exponent;
    const bool integer = GiNaC::is_a<GiNaC::numeric>(x.op(1)) &&
                         GiNaC::ex_to<GiNaC::numeric>(x.op(1)).is_integer();
    return integer ? CompareMagnitude(x.op(0), y.op(0)) : CompareSigned(x.op(0), y.op(0));
  }
  if (GiNaC::is_a<GiNaC::function>(x)) {
    if (const int by_name = Compare(GiNaC::ex_to<GiNaC::function>(x).get_name(),
                                    GiNaC::ex_to<GiNaC::function>(y).get_name());
        by_name != 0)
      return by_name;
    if (const int by_count = Compare(x.nops(), y.nops()); by_count != 0) return by_count;
    for (std::size_t k = 0; k < x.nops(); ++k)
      if (const int c = CompareSigned(x.op(k), y.op(k)); c != 0) return c;
    return 0;
  }
  return Compare(Text(x), Text(y));
}

}  // namespace dvi::dvisim
