// SPDX-License-Identifier: Apache-2.0
#include "siconos_lcp.hpp"

#include <chrono>
#include <csetjmp>
#include <cstring>
#include <stdexcept>

// Siconos builds CXSparse with 64-bit indices (SICONOS_INT64); cs.h gives the
// layout of its opaque CSparseMatrix so the compressed columns can be filled.
#include <cs.h>
#include <siconos/numerics/LCP_Solvers.h>
#include <siconos/numerics/LinearComplementarityProblem.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/NumericsSparseMatrix.h>
#include <siconos/numerics/NumericsVerbose.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/lcp_cst.h>
#include <siconos/numerics/sn_error_handling.h>

namespace dvi::bench {
namespace {

int SolverId(SiconosSolver solver) {
  switch (solver) {
    case SiconosSolver::kLemke:
      return SICONOS_LCP_LEMKE;
    case SiconosSolver::kNewtonFb:
      return SICONOS_LCP_NEWTON_FB_FBLSA;
    case SiconosSolver::kNewtonMinFb:
      return SICONOS_LCP_NEWTON_MIN_FBLSA;
    case SiconosSolver::kPgs:
      return SICONOS_LCP_PGS;
  }
  return SICONOS_LCP_LEMKE;
}

// Siconos reports fatal errors (e.g. an unsupported storage) by longjmp to a
// buffer the caller registered, or abort() otherwise. Only plain C data lives
// in this frame, so the jump skips no destructor.
int GuardedDriver(LinearComplementarityProblem* problem, double* z, double* w,
                  SolverOptions* options) {
  if (setjmp(*sn_get_jmp_buf()) != 0) {
    sn_release_jmp_buf();
    return kFatalInfo;
  }
  const int info = linearComplementarity_driver(problem, z, w, options);
  sn_release_jmp_buf();
  return info;
}

}  // namespace

std::string_view ToString(SiconosSolver solver) {
  switch (solver) {
    case SiconosSolver::kLemke:
      return "siconos-lemke";
    case SiconosSolver::kNewtonFb:
      return "siconos-newton-fb";
    case SiconosSolver::kNewtonMinFb:
      return "siconos-newton-minfb";
    case SiconosSolver::kPgs:
      return "siconos-pgs";
  }
  return "siconos-?";
}

void QuietSiconos() { numerics_set_verbose(0); }

SiconosLcp::SiconosLcp(const Lcp& lcp) : q_(lcp.q) {
  const int n = lcp.dim();
  NumericsMatrix* M = NM_create(NM_DENSE, n, n);
  // Both are column-major with leading dimension n.
  std::memcpy(M->matrix0, lcp.M.data(), sizeof(double) * static_cast<size_t>(n) * n);
  problem_ = newLCP();
  problem_->size = n;
  problem_->M = M;
  problem_->q = q_.data();
}

SiconosLcp::SiconosLcp(const SparseLcp& lcp) : q_(lcp.q) {
  const int n = lcp.dim();
  SparseMatrix M = lcp.M;
  M.makeCompressed();
  NumericsMatrix* A = NM_create(NM_SPARSE, n, n);
  NM_csc_alloc(A, M.nonZeros());
  CSparseMatrix* csc = A->matrix2->csc;
  for (int j = 0; j <= n; ++j) csc->p[j] = M.outerIndexPtr()[j];
  for (Eigen::Index k = 0; k < M.nonZeros(); ++k) {
    csc->i[k] = M.innerIndexPtr()[k];
    csc->x[k] = M.valuePtr()[k];
  }
  A->matrix2->origin = NSM_CSC;
  problem_ = newLCP();
  problem_->size = n;
  problem_->M = A;
  problem_->q = q_.data();
}

SiconosLcp::~SiconosLcp() {
  // freeLinearComplementarityProblem frees q too; q belongs to q_ here.
  problem_->q = nullptr;
  NM_free(problem_->M);
  problem_->M = nullptr;
  freeLinearComplementarityProblem(problem_);
}

SiconosOutcome SiconosLcp::Solve(SiconosSolver solver, double tolerance, int max_iterations) {
  SolverOptions* options = solver_options_create(SolverId(solver));
  if (options == nullptr) throw std::runtime_error("solver_options_create failed");
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iterations;
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;

  const int n = problem_->size;
  SiconosOutcome out;
  out.z = Eigen::VectorXd::Zero(n);
  out.w = Eigen::VectorXd::Zero(n);
  const auto start = std::chrono::steady_clock::now();
  out.info = GuardedDriver(problem_, out.z.data(), out.w.data(), options);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (out.info == kFatalInfo) out.fatal_message = sn_fatal_error_msg();
  out.error = options->dparam[SICONOS_DPARAM_RESIDU];
  out.iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
  solver_options_delete(options);
  return out;
}

}  // namespace dvi::bench
