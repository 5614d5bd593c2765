// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the scene reader and the expression compiler. Any input
// is read as a scene; the contract is a Scene or an InputError (bad input),
// nothing else: no other exception, crash, hang or sanitizer report. A scene
// that parses has its compiled expressions evaluated once at (0, x0, 0), as
// the integrators first do.
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>

#include "dvi/error.hpp"
#include "scene_file.hpp"

namespace {

// The functions of a Dvi at t = 0, x0 and u = 0: whatever they return, they
// must return (values may be anything, a NaN included).
void EvaluateOnce(const dvi::dvisim::Scene& scene) {
  const auto* dvi = std::get_if<dvi::Dvi>(&scene.problem);
  if (dvi == nullptr) return;
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(dvi->m);
  Eigen::VectorXd f(dvi->n), F(dvi->m);
  Eigen::MatrixXd fx(dvi->n, dvi->n), fu(dvi->n, dvi->m), Fx(dvi->m, dvi->n), Fu(dvi->m, dvi->m);
  dvi->f(0.0, scene.x0, u, f);
  dvi->F(0.0, scene.x0, u, F);
  dvi->f_jacobian(0.0, scene.x0, u, fx, fu);
  dvi->F_jacobian(0.0, scene.x0, u, Fx, Fu);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    EvaluateOnce(dvi::dvisim::ParseScene(text));
  } catch (const dvi::dvisim::InputError&) {
    // Bad input, answered with a message: the contract.
  }
  return 0;
}
