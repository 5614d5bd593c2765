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


def step_to_the_end(integrator):
    outcome = dvi.StepOutcome.STEP
    for _ in range(100000):
        outcome = integrator.step()
        if outcome in (dvi.StepOutcome.END, dvi.StepOutcome.FAILURE):
            break
    return outcome


def assert_same_run(a, b):
    np.testing.assert_array_equal(a.times, b.times)
    np.testing.assert_array_equal(a.states, b.states)
    np.testing.assert_array_equal(a.multipliers, b.multipliers)
    assert a.intervals == b.intervals
    assert a.events == b.events


# x' = u, u in SOL(K, u + x), K the unit ball (integrate_auto lifts it to its
# KKT system): from (3, 0), |x| falls at unit rate to 1 at t = 2, then
# x = e^(2 - t) (1, 0). With output times: step() to the end is
# integrate_auto bit for bit, advance_to stops exactly on the interval it
# runs whole, and reinit at t = 1 to (4, 0) moves the release to t = 4.
def projected_decay():
    return dvi.Dvi(n=2, m=2, f=lambda t, x, u: u, F=lambda t, x, u: u + x,
                   K=dvi.ConvexSet.ball([0.0, 0.0], 1.0))


def test_a_ball_with_output_times_steps_as_integrate_auto():
    options = dict(rtol=1e-10, atol=1e-12, output_times=np.linspace(0.0, 4.0, 41))
    one_shot = dvi.integrate_auto(projected_decay(), [3.0, 0.0], 0.0, 4.0, **options)
    assert one_shot.succeeded, one_shot.message
    stepped = dvi.AutoIntegrator(projected_decay(), [3.0, 0.0], 0.0, 4.0, **options)
    assert step_to_the_end(stepped) == dvi.StepOutcome.END
    assert_same_run(stepped.trajectory(), one_shot)

    integrator = dvi.AutoIntegrator(projected_decay(), [3.0, 0.0], 0.0, 6.0, rtol=1e-10, atol=1e-12)
    assert integrator.advance_to(1.0) == dvi.StepOutcome.STOP_TIME
    assert integrator.t == 1.0
    assert np.max(np.abs(integrator.x - [2.0, 0.0])) <= 1e-9
    integrator.reinit(1.0, [4.0, 0.0])
    assert integrator.advance_to(5.0) == dvi.StepOutcome.STOP_TIME
    assert np.max(np.abs(integrator.x - [math.exp(-1.0), 0.0])) <= 1e-8
    events = integrator.trajectory().events
    assert len(events) == 1 and abs(events[0][0] - 4.0) <= 1e-9


# Charge sharing through an ideal diode (tests/state_jump_test.cpp): x0 =
# (2, 0) admits no u, the LCS jumps to (1, 1), then v1 = v2 = e^(-t/2).
def test_a_state_jump_steps_as_integrate_auto():
    lcs = dvi.Lcs(A=np.array([[0.0, 0.0], [0.0, -1.0]]), B=np.array([[-1.0], [1.0]]),
                  C=np.array([[-1.0, 1.0]]), D=np.zeros((1, 1)))
    options = dict(rtol=1e-10, atol=1e-12)
    one_shot = dvi.integrate_auto(lcs, [2.0, 0.0], 0.0, 4.0, **options)
    assert one_shot.succeeded, one_shot.message
    stepped = dvi.AutoIntegrator(lcs, [2.0, 0.0], 0.0, 4.0, **options)
    assert np.max(np.abs(stepped.x - [1.0, 1.0])) <= 1e-12
    assert step_to_the_end(stepped) == dvi.StepOutcome.END
    run = stepped.trajectory()
    assert_same_run(run, one_shot)
    assert run.events[0][1] == "jump"
    np.testing.assert_array_equal(run.states[0], [2.0, 0.0])
    assert np.max(np.abs(run.states[-1] - math.exp(-2.0))) <= 1e-8


# A square wave s = +1, -1, +1 on [0, 1), [1, 2), [2, 3) through a one-sided
# clamp (tests/lcs_sources_test.cpp), its steps declared as breakpoints: x =
# 1 - e^(-t) up to t = 1, then -1 + (x(1) + 1) e^(-(t - 1)) until it reaches 0.
def test_source_breakpoints_step_as_integrate_auto():
    square = dvi.Dvi(n=1, m=1, f=lambda t, x, u: [(1.0 if math.floor(t) % 2 == 0 else -1.0)
                                                  - x[0] + u[0]],
                     F=lambda t, x, u: x + u, breakpoints=[1.0, 2.0, 3.0])
    options = dict(rtol=1e-10, atol=1e-12)
    one_shot = dvi.integrate_auto(square, [0.0], 0.0, 3.0, **options)
    assert one_shot.succeeded, one_shot.message
    stepped = dvi.AutoIntegrator(square, [0.0], 0.0, 3.0, **options)
    assert step_to_the_end(stepped) == dvi.StepOutcome.END
    assert_same_run(stepped.trajectory(), one_shot)
    integrator = dvi.AutoIntegrator(square, [0.0], 0.0, 3.0, **options)
    x1 = 1.0 - math.exp(-1.0)
    for t, exact in ((1.0, x1), (1.25, -1.0 + (x1 + 1.0) * math.exp(-0.25))):
        assert integrator.advance_to(t) == dvi.StepOutcome.STOP_TIME
        assert integrator.t == t
        assert abs(integrator.x[0] - exact) <= 1e-8, t


# 100 capacitors drained into ideal diodes, x_i' = -x_i - 1 + u_i,
# 0 <= u_i _|_ x_i >= 0 (n + m = 200: auto's intervals run on IDA), x0_i in
# [0.5, 2): x_i = max((1 + x0_i) e^(-t) - 1, 0) (C++:
# tests/auto_ida_live_test.cpp). step() is one IDA step, mode is the current
# one, and step() to the end is integrate_auto bit for bit.
def test_an_ida_interval_steps_live():
    n = 100
    x0 = 0.5 + 1.5 * ((37 * np.arange(n)) % n) / n
    diagonal = (list(range(n)), list(range(n)))
    lcs = dvi.Lcs.from_triplets(n, n, A=diagonal + ([-1.0] * n,), B=diagonal + ([1.0] * n,),
                                C=diagonal + ([1.0] * n,), D=([], [], []), p=[-1.0] * n)
    options = dict(rtol=1e-10, atol=1e-12)
    one_shot = dvi.integrate_auto(lcs, x0, 0.0, 2.0, **options)
    assert one_shot.succeeded, one_shot.message
    assert "IDA" in one_shot.intervals[0]["reason"]
    integrator = dvi.AutoIntegrator(lcs, x0, 0.0, 2.0, **options)
    assert integrator.step() == dvi.StepOutcome.STEP
    assert 0.0 < integrator.t < 0.01
    assert integrator.advance_to(0.7) == dvi.StepOutcome.STOP_TIME
    clamped = np.log(1 + x0) < 0.7
    assert integrator.mode == ["free" if c else "lower" for c in clamped]
    exact = np.maximum((1 + x0) * math.exp(-0.7) - 1, 0.0)
    assert np.max(np.abs(integrator.x - exact)) <= 1e-8
    stepped = dvi.AutoIntegrator(lcs, x0, 0.0, 2.0, **options)
    assert step_to_the_end(stepped) == dvi.StepOutcome.END
    assert_same_run(stepped.trajectory(), one_shot)
