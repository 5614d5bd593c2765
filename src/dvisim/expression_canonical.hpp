// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <vector>

namespace dvi::dvisim {

/// GiNaC expressions read up to what GiNaC decides by memory address, so
/// that the tape does the same arithmetic in every process (issue 27,
/// defect 3). GiNaC 1.8 orders the terms of a sum and the factors of a
/// product by hash values seeded with the address of each class's
/// type_info name (its hash_seed.h), which moves with the library's load
/// address; and where a sum is a factor of a product or the base of an
/// integer power it makes the coefficient of the sum's first term (in that
/// order) positive, so one process holds (x1 − x2 − x3)·c where another
/// holds −(x2 + x3 − x1)·c. Both differ in rounding once evaluated in
/// floating point.
///
/// This order sees neither: it compares magnitudes (e and −e alike), built
/// from symbol and function names, exact numbers and, recursively, the
/// operands in this order; a sum's terms keep their signs relative to its
/// first term. With it the tape can evaluate a sum and its negation to
/// exactly opposite values, and a product in one sequence of factors.
class CanonicalOrder {
 public:
  /// e's operands: the terms of a sum and the factors of a product sorted
  /// by magnitude (then sign); any other expression's as GiNaC has them
  /// (their position is their meaning: base and exponent, arguments).
  const std::vector<GiNaC::ex>& Operands(const GiNaC::ex& e);
  /// Whether e is written as a negative magnitude: a negative number, a
  /// sum whose first term in this order is negative, a product with an odd
  /// number of negative factors, an odd power of a negative base.
  bool Negative(const GiNaC::ex& e);

 private:
  /// < 0, 0, > 0 as |a| comes before, is, or comes after |b|.
  int CompareMagnitude(const GiNaC::ex& a, const GiNaC::ex& b);
  /// By sign, then magnitude: where the sign is part of the meaning
  /// (function arguments, non-integer powers).
  int CompareSigned(const GiNaC::ex& a, const GiNaC::ex& b);

  // Looked up only (GiNaC's ex_is_less finds an equal expression in any
  // process), never iterated.
  std::map<GiNaC::ex, std::vector<GiNaC::ex>, GiNaC::ex_is_less> operands_;
  std::map<GiNaC::ex, bool, GiNaC::ex_is_less> negative_;
};

}  // namespace dvi::dvisim
