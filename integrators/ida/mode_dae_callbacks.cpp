// SPDX-License-Identifier: Apache-2.0
#include "ida/mode_dae_callbacks.hpp"

#include <algorithm>

#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "events/user_roots.hpp"
#include "sundials/callbacks.hpp"

namespace dvi::internal {

// IDA's convention: 0 success, < 0 unrecoverable.
int ModeDaeResidualCallback(realtype, N_Vector y, N_Vector yp, N_Vector res, void* user_data) {
  auto& data = *static_cast<ModeDaeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.residual_evals;
    data.dae->Residual(N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(res));
    return 0;
  });
}

// ∂res/∂y + cj ∂res/∂y' into IDA's matrix: compressed columns for KLU (IDA
// zeroes the matrix, pattern included, before each call), or dense.
int ModeDaeJacobianCallback(realtype, realtype cj, N_Vector, N_Vector, N_Vector, SUNMatrix J,
                     void* user_data, N_Vector, N_Vector, N_Vector) {
  auto& data = *static_cast<ModeDaeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.jacobian_evals;
    const SparseMatrix& jacobian = data.dae->Jacobian(cj);
    const long columns = jacobian.cols();
    if (data.sparse) {
      if (SUNSparseMatrix_NNZ(J) < jacobian.nonZeros()) return -1;
      sunindextype* pointers = SUNSparseMatrix_IndexPointers(J);
      sunindextype* rows = SUNSparseMatrix_IndexValues(J);
      std::copy(jacobian.outerIndexPtr(), jacobian.outerIndexPtr() + columns + 1, pointers);
      std::copy(jacobian.innerIndexPtr(), jacobian.innerIndexPtr() + jacobian.nonZeros(), rows);
      std::copy(jacobian.valuePtr(), jacobian.valuePtr() + jacobian.nonZeros(),
                SUNSparseMatrix_Data(J));
    } else {
      SUNMatZero(J);
      for (long k = 0; k < columns; ++k) {
        double* column = SUNDenseMatrix_Column(J, k);
        for (SparseMatrix::InnerIterator it(jacobian, k); it; ++it) column[it.row()] = it.value();
      }
    }
    return 0;
  });
}

int ModeDaeRootCallback(realtype t, N_Vector y, N_Vector, realtype* g, void* user_data) {
  auto& data = *static_cast<ModeDaeCallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    const double* values = N_VGetArrayPointer(y);
    data.dae->Roots(values, g);
    if (data.user_events && !data.user_events->empty()) {
      const int n = data.dae->n(), m = data.dae->m();
      data.user_x = Eigen::Map<const Eigen::VectorXd>(values, n);
      data.user_u = Eigen::Map<const Eigen::VectorXd>(values + n, m);
      EvaluateUserRoots(*data.user_events, t, data.user_x, data.user_u, g + 2 * m);
    }
    return 0;
  });
}

void ModeDaeErrorHandler(int, const char*, const char* function, char* message, void* user_data) {
  auto& data = *static_cast<ModeDaeCallbackData*>(user_data);
  data.ida_message = std::string(function) + ": " + message;
}

}  // namespace dvi::internal
