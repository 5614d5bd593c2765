// SPDX-License-Identifier: Apache-2.0
// The CVODE family OdeMethod::kAuto picks (issue 31).
#include "cvode/ode_family.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace dvi::internal {

OdeMethod ChooseOdeFamily(const Eigen::MatrixXd& J, double rtol, double horizon,
                          std::string* why) {
  if (J.rows() > kLargestAnalysed) {
    if (why) *why = "bdf (n > " + std::to_string(kLargestAnalysed) + ": not analysed)";
    return OdeMethod::kBdf;
  }
  if (J.rows() == 0 || !J.allFinite()) {
    if (why) *why = "adams (no finite Jacobian to show stiffness)";
    return OdeMethod::kAdams;
  }
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(J, false).eigenvalues();
  double decay = 0, follow = 1 / horizon, slowest = lambda.cwiseAbs().minCoeff();
  for (const auto& l : lambda) {
    decay = std::max(decay, -l.real());
    follow = std::max(follow, std::abs(l.imag()));
  }
  follow = std::max(follow, slowest);
  const double h_sigma = std::pow(rtol, 0.2) / follow * decay;
  const OdeMethod method = h_sigma > kAdamsStability ? OdeMethod::kBdf : OdeMethod::kAdams;
  if (why) {
    std::ostringstream text;
    text.precision(3);
    text << ToString(method) << " (h·σ = " << h_sigma << (method == OdeMethod::kBdf ? " > " : " <= ")
         << kAdamsStability << ": σ = " << decay << ", ω = " << follow << ")";
    *why = text.str();
  }
  return method;
}

}  // namespace dvi::internal
