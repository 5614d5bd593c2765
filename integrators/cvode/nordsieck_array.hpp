// SPDX-License-Identifier: Apache-2.0
// CVODE's Nordsieck history read in place (issue 31: a step's Taylor
// coefficients without q + 1 CVodeGetDky calls).
#pragma once

#include <Eigen/Dense>
#include <sundials/sundials_nvector.h>

namespace dvi::internal {

/// CVODE's Nordsieck array zn[j] = hʲ y⁽ʲ⁾/j! (j = 0…q, h the last step's
/// size), found in CVODE's memory block: CVODE's public API gives zn[0] and
/// zn[1] (CVodeGetNonlinearSystemData) but no further column, and
/// CVodeGetDky one derivative a call for about 1K instructions (a sum over
/// all q + 1 columns) where the column alone is a copy. Debian's
/// libsundials-dev ships no cvode_impl.h, so no private header: the array
/// is the N_Vector slots zn[0], zn[1] next to each other, looked for by the
/// two public pointers among the block's first words (SUNDIALS 2 … 7 keep
/// zn there, a fixed array of the struct), on SUNDIALS 6 only (the version
/// whose CVodeGetDky it repeats; EventDrivenRun also compares its first
/// read with CVodeGetDky's, bit for bit). Owns nothing.
class NordsieckArray {
 public:
  /// Looks zn up in cvode's memory (after CVodeInit, which allocates it);
  /// false (and every later Taylor false) where it is not found.
  bool Locate(void* cvode);
  bool located() const { return zn_ != nullptr; }
  /// Forgets the array: the caller's CVodeGetDky from then on.
  void Forget() { zn_ = nullptr; }
  /// y⁽ᵏ⁾(t_n)/k! of the last step (size h > 0, order q) into column k of
  /// taylor, k = first…q: CVodeGetDky(t_n, k)/k! to the bit (its
  /// arithmetic: k!·zn[k], then times 1/hᵏ, then over k!). False when not
  /// located.
  bool Taylor(double h, int q, int first, Eigen::MatrixXd& taylor) const;

 private:
  const N_Vector* zn_ = nullptr;
};

}  // namespace dvi::internal
