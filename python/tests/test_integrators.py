# SPDX-License-Identifier: Apache-2.0
"""The integrators from Python against exact solutions, and errors as
exceptions carrying dvi's message."""
import math

import numpy as np
import pytest

import dvi

# CVODE's / IDA's local error test at rtol 1e-10 leaves event times within
# about 100 rtol of the exact ones (README's quick start uses the same bound).
EVENT_TOLERANCE = 1e-8
# Backward Euler at h = 1e-3 is first order: the clamp time within a few h.
STEPPING_TOLERANCE = 5e-3


def clamp_lcs():
    one = np.ones((1, 1))
    return dvi.Lcs(A=-one, B=one, C=one, D=0 * one, p=[-1.0])


def saturated_decay():
    """x' = u, u in SOL([-1, 1], u + x): u = clip(-x); from x = 3 the switch
    to the free mode is at t = 2, x = e^(2 - t) after."""
    return dvi.Dvi(
        n=1, m=1,
        f=lambda t, x, u: u,
        F=lambda t, x, u: u + x,
        K=dvi.ConvexSet.box([-1.0], [1.0]),
        f_jacobian=lambda t, x, u: (np.zeros((1, 1)), np.ones((1, 1))),
        F_jacobian=lambda t, x, u: (np.ones((1, 1)), np.ones((1, 1))),
    )


@pytest.mark.parametrize("integrate", [dvi.integrate_event, dvi.integrate_ida, dvi.integrate_auto])
def test_clamp_time_is_ln2(integrate):
    run = integrate(clamp_lcs(), [1.0], 0.0, 2.0, rtol=1e-10, atol=1e-12)
    assert run.succeeded, run.message
    assert run.status == "success"
    assert len(run.events) == 1
    assert abs(run.event_times[0] - math.log(2)) <= EVENT_TOLERANCE
    assert run.states.shape == (len(run.times), 1)
    assert run.multipliers.shape == (len(run.times), 1)
    assert abs(run.states[-1, 0]) <= EVENT_TOLERANCE
    assert run.certificate["certified"]
    assert run.intervals[0]["linear_solver"] in ("dense", "klu")
    assert run.stats["steps"] > 0


def test_stepping_with_keywords():
    run = dvi.integrate_stepping(clamp_lcs(), [1.0], 0.0, 2.0, h=1e-3, theta=0.0)
    assert run.succeeded, run.message
    assert run.intervals[0]["method"] == "stepping"
    assert run.intervals[0]["linear_solver"] is None
    exact = 2 * np.exp(-run.times) - 1
    clamped = np.maximum(exact, 0)
    assert np.max(np.abs(run.states[:, 0] - clamped)) <= STEPPING_TOLERANCE


def test_dvi_with_python_callables_matches_exact():
    times = list(np.linspace(0.0, 5.0, 11))
    run = dvi.integrate_event(saturated_decay(), [3.0], 0.0, 5.0, rtol=1e-10, atol=1e-12,
                              output_times=times)
    assert run.succeeded, run.message
    assert abs(run.event_times[0] - 2.0) <= EVENT_TOLERANCE
    exact = np.where(run.times <= 2, 3 - run.times, np.exp(2 - run.times))
    assert np.max(np.abs(run.states[:, 0] - exact)) <= EVENT_TOLERANCE
    assert run.events[0][1] == "left-bound"


def test_filippov_relay_slides_at_zero():
    """x' = -sgn(x) from x = 1: reaches 0 at t = 1 and slides there."""
    relay = dvi.Filippov(n=1, k=1, f0=lambda t, x: [0.0], f1=lambda t, x: [[-1.0]],
                         h=lambda t, x: x)
    run = dvi.integrate_auto(relay, [1.0], 0.0, 2.0, rtol=1e-10, atol=1e-12)
    assert run.succeeded, run.message
    assert abs(run.states[-1, 0]) <= EVENT_TOLERANCE


def test_projected_dynamics_stays_in_k():
    """x' in -(x - c) - N(x; R+) with c = -1: x = e^-t... until 0, then held."""
    pds = dvi.ProjectedDynamics.affine(np.eye(1), [-1.0], dvi.ConvexSet.orthant(1))
    run = dvi.integrate_stepping(pds, [1.0], 0.0, 2.0, h=1e-3)
    assert run.succeeded, run.message
    assert np.min(run.states) >= -1e-12
    assert abs(run.states[-1, 0]) <= 1e-12


def test_sparse_triplets_equal_dense():
    dense = dvi.integrate_event(clamp_lcs(), [1.0], 0.0, 2.0, rtol=1e-10)
    entry = ([0], [0], [1.0])
    sparse = dvi.Lcs.from_triplets(1, 1, A=([0], [0], [-1.0]), B=entry, C=entry,
                                   D=([], [], []), p=[-1.0])
    run = dvi.integrate_event(sparse, [1.0], 0.0, 2.0, rtol=1e-10)
    assert run.event_times[0] == dense.event_times[0]


def test_solve_lcp():
    result = dvi.solve(dvi.Lcp(M=np.array([[2.0, 1.0], [1.0, 2.0]]), q=np.array([-1.0, 1.0])))
    assert result.solved
    np.testing.assert_allclose(result.z, [0.5, 0.0], atol=1e-10)
    np.testing.assert_allclose(result.w, [0.0, 1.5], atol=1e-10)


def test_bad_input_raises_with_dvis_message():
    with pytest.raises(ValueError, match="x0 has 2 entries, expected 1"):
        dvi.integrate_event(clamp_lcs(), [1.0, 2.0], 0.0, 2.0)
    with pytest.raises(dvi.InvalidInputError, match="unknown keyword.*rtoll"):
        dvi.integrate_event(clamp_lcs(), [1.0], 0.0, 2.0, rtoll=1e-6)
    with pytest.raises(ValueError, match="linear_solver: unknown value \"lu\""):
        dvi.integrate_event(clamp_lcs(), [1.0], 0.0, 2.0, linear_solver="lu")
    with pytest.raises(ValueError, match="entry 0 at \\(1, 0\\) is outside"):
        dvi.Lcs.from_triplets(1, 1, A=([1], [0], [1.0]), B=([], [], []), C=([], [], []),
                              D=([], [], []))


def test_wrong_sized_callable_is_named():
    bad = dvi.Dvi(n=1, m=1, f=lambda t, x, u: [0.0, 1.0], F=lambda t, x, u: u + x,
                  K=dvi.ConvexSet.box([-1.0], [1.0]))
    with pytest.raises(ValueError, match="Dvi.f: returned 2 entries, expected 1"):
        run = dvi.integrate_event(bad, [3.0], 0.0, 1.0)
        if not run.succeeded:  # a failure inside the run carries the message
            raise ValueError(run.message)


def test_version():
    assert dvi.__version__.count(".") == 2


def test_diode_bridge_example_matches_the_exact_rlc_state():
    """python/examples/diode_bridge.py's run (its plot needs matplotlib)."""
    import diode_bridge
    run = diode_bridge.run_bridge(samples=101)
    assert run.succeeded, run.message
    # Ideal diodes: the tank always sees R, a damped RLC oscillation.
    L, C, R, v0 = 1e-2, 1e-6, 1e3, 10.0
    alpha = 1 / (2 * R * C)
    omega = np.sqrt(1 / (L * C) - alpha ** 2)
    t = run.times
    v = np.exp(-alpha * t) * (np.cos(omega * t) * v0
                              + np.sin(omega * t) / omega * (-1 / (R * C) + alpha) * v0)
    # The README's goal for auto on the bridge at its default rtol 1e-8: 6e-6 V.
    assert np.max(np.abs(run.states[:, 0] - v)) <= 6e-6


def test_diode_bridge_picture(tmp_path):
    pytest.importorskip("matplotlib", reason="python3-matplotlib not installed")
    import diode_bridge
    diode_bridge.main(tmp_path / "bridge.png")
    assert (tmp_path / "bridge.png").stat().st_size > 0


def test_a_callables_exception_reaches_the_caller():
    def broken(t, x, u):
        raise ZeroDivisionError("boom in f")

    problem = dvi.Dvi(n=1, m=1, f=broken, F=lambda t, x, u: u + x,
                      K=dvi.ConvexSet.box([-1.0], [1.0]))
    for integrate in (dvi.integrate_event, dvi.integrate_stepping, dvi.integrate_auto):
        with pytest.raises(ZeroDivisionError, match="boom in f"):
            integrate(problem, [3.0], 0.0, 1.0)


def test_multiplier_at_between_samples_solves_the_mode():
    """u = -1 until the switch at t = 2, then -e^(2 - t): multiplier_at on a
    10x finer grid within 10x the error at the samples (issue 33), where the
    next sample's value would be off by the step times |u'|."""
    run = dvi.integrate_event(saturated_decay(), [3.0], 0.0, 5.0, rtol=1e-10, atol=1e-12)
    assert run.succeeded, run.message

    def exact_u(t):
        return -1.0 if t <= 2 else -np.exp(2 - t)

    sample_error = max(abs(u[0] - exact_u(t)) for t, u in zip(run.times, run.multipliers))
    fine = np.linspace(0.0, 5.0, 10 * len(run.times))
    dense_error = max(abs(run.multiplier_at(t)[0] - exact_u(t)) for t in fine)
    assert dense_error <= 10 * max(sample_error, 1e-12), (dense_error, sample_error)
