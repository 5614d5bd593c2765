# SPDX-License-Identifier: Apache-2.0
"""Lcs from scipy.sparse matrices: the same Lcs, so the same answer, as the
dense input; bad shapes and NaN named by the argument."""
import json
import pathlib

import numpy as np
import pytest

import dvi

scipy_sparse = pytest.importorskip("scipy.sparse")

REPO = pathlib.Path(__file__).resolve().parents[2]


def diode_bridge():
    """examples/scenes/diode_bridge.json's LCS (D positive semidefinite, u
    not unique while B u is: Proposition 5.1), with x0 and horizon. Its
    matrices are mostly exact zeros, which a sparse input may hold
    explicitly."""
    scene = json.loads((REPO / "examples" / "scenes" / "diode_bridge.json").read_text())
    A, B, C, D = (np.array(scene["problem"][k], dtype=float) for k in "ABCD")
    return (A, B, C, D), scene["x0"], scene["horizon"]


def with_explicit_zeros_and_duplicates(matrix):
    """A coo matrix equal to `matrix` that stores every zero explicitly and
    splits each nonzero into two summed halves."""
    rows, cols = np.indices(matrix.shape)
    rows, cols, values = rows.ravel(), cols.ravel(), matrix.ravel()
    return scipy_sparse.coo_matrix(
        (np.concatenate([values / 2, values / 2]),
         (np.concatenate([rows, rows]), np.concatenate([cols, cols]))), shape=matrix.shape)


FORMS = {
    "csr": scipy_sparse.csr_matrix,
    "csc": scipy_sparse.csc_matrix,
    "coo": scipy_sparse.coo_matrix,
    "coo with zeros and duplicates": with_explicit_zeros_and_duplicates,
}


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("integrate", [dvi.integrate_event, dvi.integrate_auto])
def test_sparse_equals_dense(form, integrate):
    matrices, x0, horizon = diode_bridge()
    make = FORMS[form]
    dense = integrate(dvi.Lcs(*matrices), x0, 0.0, horizon)
    sparse = integrate(dvi.Lcs(*(make(M) for M in matrices)), x0, 0.0, horizon)
    assert dense.succeeded and sparse.succeeded
    # The same Lcs entry for entry: the same floating-point operations.
    assert np.array_equal(dense.times, sparse.times)
    assert np.array_equal(dense.states, sparse.states)
    assert np.array_equal(dense.multipliers, sparse.multipliers)
    assert dense.event_times.size > 0  # the diodes do switch


def test_mixed_dense_and_sparse():
    (A, B, C, D), x0, horizon = diode_bridge()
    dense = dvi.integrate_event(dvi.Lcs(A, B, C, D), x0, 0.0, horizon)
    mixed = dvi.integrate_event(dvi.Lcs(scipy_sparse.csr_matrix(A), B, C, D), x0, 0.0, horizon)
    assert np.array_equal(dense.states, mixed.states)


def test_sparse_inputs_untouched():
    (A, B, C, D), _, _ = diode_bridge()
    coo = with_explicit_zeros_and_duplicates(B)
    nnz = coo.nnz
    dvi.Lcs(A, coo, C, D)
    assert coo.nnz == nnz


def test_wrong_shape_names_the_argument():
    (A, B, C, D), _, _ = diode_bridge()
    with pytest.raises(dvi.InvalidInputError, match=r"Lcs\.B: 1×4, expected 2×4"):
        dvi.Lcs(A, scipy_sparse.csr_matrix(B[:1]), C, D)


def test_nan_names_the_argument_and_entry():
    (A, B, C, D), _, _ = diode_bridge()
    C = C.copy()
    C[1, 1] = np.nan
    with pytest.raises(dvi.InvalidInputError, match=r"Lcs\.C\(1, 1\) = nan is not finite"):
        dvi.Lcs(A, B, scipy_sparse.csc_matrix(C), D)


def test_not_a_matrix_names_the_argument():
    (A, B, C, D), _, _ = diode_bridge()
    with pytest.raises(dvi.InvalidInputError, match=r"Lcs\.D: expected a 2-d array"):
        dvi.Lcs(A, B, C, "D")
