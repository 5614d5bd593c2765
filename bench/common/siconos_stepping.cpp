// SPDX-License-Identifier: Apache-2.0
#include "siconos_stepping.hpp"

#include <chrono>
#include <cstring>
#include <ctime>
#include <exception>
#include <memory>
#include <string>

#include <siconos/numerics/NumericsVerbose.h>
#include <siconos/numerics/lcp_cst.h>

#include <ComplementarityConditionNSL.hpp>
#include <EulerMoreauOSI.hpp>
#include <FirstOrderLinearDS.hpp>
#include <FirstOrderLinearR.hpp>
#include <FirstOrderLinearTIDS.hpp>
#include <FirstOrderLinearTIR.hpp>
#include <Interaction.hpp>
#include <LCP.hpp>
#include <NonSmoothDynamicalSystem.hpp>
#include <SiconosVector.hpp>
#include <SimpleMatrix.hpp>
#include <TimeDiscretisation.hpp>
#include <TimeStepping.hpp>

#include "dvi/error.hpp"

namespace dvi::bench {
namespace {

// Siconos' dense SimpleMatrix is a column-major ublas matrix, as is Eigen's
// default, so the entries are copied in one block.
std::shared_ptr<SimpleMatrix> ToSiconos(const SparseMatrix& m) {
  const Eigen::MatrixXd dense(m);
  auto out = std::make_shared<SimpleMatrix>(static_cast<unsigned>(dense.rows()),
                                            static_cast<unsigned>(dense.cols()));
  std::memcpy(out->getArray(), dense.data(), sizeof(double) * static_cast<size_t>(dense.size()));
  return out;
}

std::shared_ptr<SiconosVector> ToSiconos(const Eigen::VectorXd& v) {
  auto out = std::make_shared<SiconosVector>(static_cast<unsigned>(v.size()));
  std::memcpy(out->getArray(), v.data(), sizeof(double) * static_cast<size_t>(v.size()));
  return out;
}

Eigen::VectorXd FromSiconos(const SiconosVector& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.getArray(), v.size());
}

// Siconos' default check only prints a warning to stdout when the LCP
// solver fails (info != 0) and carries on; this hook counts the failures
// instead. TimeStepping takes a plain function pointer, hence the file-level
// state (the benchmark runs one simulation at a time).
struct SolverFailures {
  long count = 0;
  int last_info = 0;
};
SolverFailures g_failures;

void CountSolverFailure(int info, Simulation*) {
  if (info == 0) return;
  ++g_failures.count;
  g_failures.last_info = info;
}

// The b(t) and e(t) plugins are plain function pointers too: they read the
// base vectors and sources of the one simulation running from here.
struct Sources {
  Eigen::VectorXd p, q;
  const SiconosSteppingOptions* options = nullptr;
};
Sources g_sources;

void PluggedB(double t, unsigned int size, double* b, unsigned int, double*) {
  Eigen::Map<Eigen::VectorXd>(b, size) = g_sources.p + g_sources.options->p_source(t);
}

void PluggedE(double t, unsigned int size, double* e, unsigned int, double*) {
  Eigen::Map<Eigen::VectorXd>(e, size) = g_sources.q + g_sources.options->q_source(t);
}

}  // namespace

SiconosSteppingResult RunSiconosStepping(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                         const SiconosSteppingOptions& options) {
  if (lcs.K.kind() != ConvexSet::Kind::kOrthant) {
    throw InvalidInputError("RunSiconosStepping: lcs.K must be the orthant (Siconos' LCP)");
  }
  SiconosSteppingResult result;
  numerics_set_verbose(0);
  try {
    const double t_end = t0 + static_cast<double>(options.steps) * options.h;
    g_sources = {lcs.p, lcs.q, &options};
    std::shared_ptr<FirstOrderLinearDS> ds;
    if (options.p_source) {
      ds = std::make_shared<FirstOrderLinearDS>(ToSiconos(x0), ToSiconos(lcs.A),
                                                ToSiconos(Eigen::VectorXd(lcs.p + options.p_source(t0))));
      ds->setComputebFunction(&PluggedB);
    } else {
      ds = std::make_shared<FirstOrderLinearTIDS>(ToSiconos(x0), ToSiconos(lcs.A), ToSiconos(lcs.p));
    }
    std::shared_ptr<Relation> relation;
    if (options.q_source) {
      auto plugged = std::make_shared<FirstOrderLinearR>(ToSiconos(lcs.C), ToSiconos(lcs.B));
      plugged->setDPtr(ToSiconos(lcs.D));
      plugged->setePtr(ToSiconos(Eigen::VectorXd(lcs.q + options.q_source(t0))));
      plugged->getPlugine()->setComputeFunction(reinterpret_cast<void*>(&PluggedE));
      relation = plugged;
    } else {
      auto constant = std::make_shared<FirstOrderLinearTIR>(ToSiconos(lcs.C), ToSiconos(lcs.B));
      constant->setDPtr(ToSiconos(lcs.D));
      constant->setePtr(ToSiconos(lcs.q));
      relation = constant;
    }
    auto law = std::make_shared<ComplementarityConditionNSL>(static_cast<unsigned>(lcs.m()));
    auto interaction = std::make_shared<Interaction>(law, relation);
    auto nsds = std::make_shared<NonSmoothDynamicalSystem>(t0, t_end);
    nsds->insertDynamicalSystem(ds);
    nsds->link(interaction, ds);

    // Siconos' θ weights the new state, ours the old one. With useGamma (and
    // not useGammaForRelation) EulerMoreauOSI solves, for a linear TIDS/TIR,
    //   x⁺ = x + h[A((1−θ_S)x + θ_S x⁺) + b + γ r⁺ + (1−γ) r],  r = Bλ,
    //   0 ≤ λ⁺ ⊥ C x⁺ + D λ⁺ + e ≥ 0
    // (computeFreeState / updateState / computeFreeOutput, LCP matrix
    // D + h γ C W⁻¹ B with W = I − h θ_S A): scheme (7.2) with θ = 1 − θ_S.
    auto osi = std::make_shared<EulerMoreauOSI>(1.0 - options.theta, options.gamma);
    // The two-argument constructor already sets these; they are the scheme.
    osi->setUseGammaForRelation(false);
    osi->setUseGamma(true);
    auto lcp = std::make_shared<LCP>(SICONOS_LCP_LEMKE);
    auto td = std::make_shared<TimeDiscretisation>(t0, options.h);
    auto simulation = std::make_shared<TimeStepping>(nsds, td, osi, lcp);
    // A linear system: one Newton iteration per step is the exact step.
    simulation->setNewtonOptions(SICONOS_TS_LINEAR);
    simulation->setCheckSolverFunction(&CountSolverFailure);
    g_failures = {};

    if (options.r0.size() > 0) ds->r()->setBlock(0, *ToSiconos(options.r0));

    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    simulation->initialize();
    const SiconosVector& x = *ds->x();
    for (long k = 1; k <= options.steps; ++k) {
      simulation->computeOneStep();
      if (k % options.record_stride == 0 || k == options.steps) {
        result.recorded_steps.push_back(k);
        result.states.push_back(FromSiconos(x));
      }
      simulation->nextStep();
    }
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    result.ok = g_failures.count == 0;
    if (!result.ok) {
      result.message = "Siconos' Lemke failed at " + std::to_string(g_failures.count) + " of " +
                       std::to_string(options.steps) +
                       " steps (last info = " + std::to_string(g_failures.last_info) + ")";
    }
  } catch (const std::exception& e) {
    result.message = std::string("Siconos exception: ") + e.what();
  }
  return result;
}

}  // namespace dvi::bench
