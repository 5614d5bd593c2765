# SPDX-License-Identifier: Apache-2.0
"""dvi.AutoIntegrator (issue 33): the automatic driver as an object from
Python, on the zoo's twisting controller (tests/support/zoo), whose Zeno
accumulation auto extrapolates (C++: tests/auto_integrator_test.cpp)."""
import math

import numpy as np

import dvi

# x1'' = -a sgn(x1) - b sgn(x1') as x' = A x + B u, u_j in SOL([-1, 1], -x_j),
# a = 2, b = 1, from (1, 0): t* = 4.4614.
A = np.array([[0.0, 1.0], [0.0, 0.0]])
B = np.array([[0.0, 0.0], [-2.0, -1.0]])
OPTIONS = dict(rtol=1e-10, atol=1e-14, h=1e-3)
HORIZON = 6.0
# The split run and the one run each within their tolerance of the exact
# solution: 2.1e-10 apart at the stops (the C++ test's kSplitTolerance).
SPLIT_TOLERANCE = 1e-9


def twisting_controller():
    return dvi.Lcs(A=A, B=B, C=-np.eye(2), D=np.zeros((2, 2)),
                   K=dvi.ConvexSet.box([-1.0, -1.0], [1.0, 1.0]))


def test_hundred_advance_to_calls_match_one_run():
    one_shot = dvi.integrate_auto(twisting_controller(), [1.0, 0.0], 0.0, HORIZON, **OPTIONS)
    assert one_shot.succeeded, one_shot.message
    methods = [interval["method"] for interval in one_shot.intervals]
    assert "zeno-extrapolation" in methods

    # advance_to(t_end) in one call: integrate_auto, bit for bit.
    whole = dvi.AutoIntegrator(twisting_controller(), [1.0, 0.0], 0.0, HORIZON, **OPTIONS)
    assert whole.advance_to(HORIZON) == dvi.StepOutcome.END
    run = whole.trajectory()
    np.testing.assert_array_equal(run.times, one_shot.times)
    np.testing.assert_array_equal(run.states, one_shot.states)
    assert run.intervals == one_shot.intervals

    split = dvi.AutoIntegrator(twisting_controller(), [1.0, 0.0], 0.0, HORIZON, **OPTIONS)
    stops = 100
    seen = set()
    for k in range(1, stops + 1):
        stop = HORIZON * k / stops
        outcome = split.advance_to(stop)
        assert outcome == (dvi.StepOutcome.STOP_TIME if k < stops else dvi.StepOutcome.END)
        assert split.t == stop
        seen.add(split.method)
        assert np.max(np.abs(split.x - one_shot.state_at(stop))) <= SPLIT_TOLERANCE, stop
    assert seen == {"event", "zeno-extrapolation"}
    run = split.trajectory()
    assert run.succeeded, run.message
    assert [i["method"] for i in run.intervals] == methods
    for a, b in zip(run.intervals, one_shot.intervals):
        assert math.isclose(a["to"], b["to"], rel_tol=0, abs_tol=SPLIT_TOLERANCE)
    np.testing.assert_array_equal(run.states[-1], [0.0, 0.0])
    assert "AutoIntegrator" in repr(split)
