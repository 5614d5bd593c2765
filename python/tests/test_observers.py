# SPDX-License-Identifier: Apache-2.0
"""Observers and user events from Python (issue 33): observer= and events=
of integrate_event and dvi.EventDrivenIntegrator, and of integrate_auto and
dvi.AutoIntegrator, against exact solutions (the C++
tests/event_driven_observer_test.cpp's and auto_observer_test.cpp's), the
exceptions of the callables reaching the caller as themselves, and the
refusals."""
import math

import numpy as np
import pytest

import dvi

# Tight enough that an event's time is known to 1e-10 (the C++ tests').
RTOL, ATOL = 1e-12, 1e-14
# States of size <= 1 over a few hundred steps of local error <= 1e-12.
STATE_ERROR = 1e-10
# An event's time: the root finder's 100 eps (|t| + |h|) plus the state's
# error over |x'| >= 0.5 at the crossing.
EVENT_TIME_ERROR = 1e-10


def diode():
    """v' = -v - 1 + u, 0 <= u ⊥ v >= 0 from v = 1: v = 2 e^-t - 1 until the
    clamp at ln 2, then v = 0, u = 1 (the README's quick start)."""
    one = np.ones((1, 1))
    return dvi.Lcs(A=-one, B=one, C=one, D=0 * one, p=[-1.0])


def diode_v(t):
    return 2 * math.exp(-t) - 1 if t < math.log(2) else 0.0


def callable_diode():
    """The same circuit as a Dvi of Python callables."""
    return dvi.Dvi(n=1, m=1, f=lambda t, x, u: -x - 1 + u, F=lambda t, x, u: x)


@pytest.mark.parametrize("problem", [diode(), callable_diode()])
def test_observer_sees_every_sample_in_order_at_the_exact_solution(problem):
    seen = []
    run = dvi.integrate_event(problem, [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL,
                              observer=seen.append)
    assert run.succeeded, run.message
    # Without output times every step is sampled: one observation per row.
    assert [obs.t for obs in seen] == list(run.times)
    np.testing.assert_array_equal([obs.x for obs in seen], run.states)
    np.testing.assert_array_equal([obs.u for obs in seen], run.multipliers)
    assert max(abs(obs.x[0] - diode_v(obs.t)) for obs in seen) <= STATE_ERROR
    points = [obs.point for obs in seen]
    assert points[0] == "start" and points.count("start") == 1
    assert points.count("event") == 1 and set(points) == {"start", "step", "event"}
    event = seen[points.index("event")]
    assert abs(event.t - math.log(2)) <= EVENT_TIME_ERROR
    assert abs(event.u[0] - 1) <= 1e-8 and event.mode == ["free"]  # the right limit
    assert seen[0].mode == ["lower"]
    assert repr(seen[0]) == "<dvi.Observation t = 0.0 (start), mode l>"
    with pytest.raises(ValueError):
        seen[0].x[0] = 5.0  # read-only


def test_observer_sees_output_times():
    outputs = [0.1 * k for k in range(1, 21)]
    seen = []
    run = dvi.integrate_event(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL,
                              output_times=outputs, observer=lambda obs: seen.append(obs))
    assert run.succeeded, run.message
    assert [obs.t for obs in seen if obs.point == "output-time"] == outputs[:-1]
    assert all(a.t <= b.t for a, b in zip(seen, seen[1:]))
    assert max(abs(obs.x[0] - diode_v(obs.t)) for obs in seen) <= STATE_ERROR
    # Every accepted step ends at a step end but the one cut at the clamp.
    assert sum(obs.point == "step" for obs in seen) == run.stats["steps"] - 1


@pytest.mark.parametrize("stop", [True, "stop", np.bool_(True)])
def test_observer_stops_the_run_where_it_asks(stop):
    seen = []

    def observer(obs):
        seen.append(obs.x[0])
        return stop if obs.x[0] < 0.5 else None

    run = dvi.integrate_event(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL, observer=observer)
    assert run.status == "stopped-by-user" and "observer" in run.message
    # The first state below 0.5 (v crosses it at ln(4/3)), and nothing after.
    assert seen[-1] < 0.5 <= seen[-2]
    assert run.times[-1] > math.log(4 / 3) and len(run.times) == len(seen)

    integrator = dvi.EventDrivenIntegrator(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL,
                                           observer=observer)
    assert integrator.advance_to(2.0) == dvi.StepOutcome.USER_STOP
    assert str(dvi.StepOutcome.USER_STOP) == "user-stop"
    assert integrator.step() == dvi.StepOutcome.USER_STOP  # over: no further step
    assert integrator.t == run.times[-1] and integrator.status == "stopped-by-user"


@pytest.mark.parametrize("go_on", [None, False, "continue", np.bool_(False)])
def test_observer_replies_that_go_on(go_on):
    run = dvi.integrate_event(diode(), [1.0], 0.0, 2.0, observer=lambda obs: go_on)
    assert run.succeeded and run.times[-1] == 2.0


def test_stop_event_ends_the_run_at_ln_4_3():
    """g = v - 1/2 falling, action stop: v = 2 e^-t - 1 = 1/2 at t = ln(4/3)."""
    half = dvi.UserEvent(lambda t, x, u: x[0] - 0.5, direction="falling", action="stop")
    assert (half.direction, half.action, repr(half)) == (
        "falling", "stop", "<dvi.UserEvent falling, stop>")
    run = dvi.integrate_event(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL, events=[half])
    assert run.status == "stopped-by-user" and "user event 0" in run.message
    assert abs(run.times[-1] - math.log(4 / 3)) <= EVENT_TIME_ERROR
    assert abs(run.states[-1, 0] - 0.5) <= STATE_ERROR
    assert run.events == [(run.times[-1], "user", 0)]

    integrator = dvi.EventDrivenIntegrator(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL,
                                           events=[half])
    assert integrator.advance_to(1.0) == dvi.StepOutcome.USER_STOP
    assert abs(integrator.t - math.log(4 / 3)) <= EVENT_TIME_ERROR

    # A rising one never fires: v only falls (the clamp is the one event).
    rising = dvi.UserEvent(lambda t, x, u: x[0] - 0.5, direction="rising")
    run = dvi.integrate_event(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL, events=[rising])
    assert run.succeeded and [kind for _, kind, _ in run.events] == ["left-bound"]


# A sampled-data relay controller (the C++ test's): x = (v, s, τ),
# v' = s - v + u with the diode 0 <= u ⊥ v >= 0, the held control s' = 0 and
# the clock τ' = 1. Every T the user event g = τ - T resets τ = 0 and sets
# s = +1 if v < r, else -1. Exact: v = s + (v_k - s) e^-Δ, clamped at 0
# (u = 1) once it reaches it with s = -1.
T, REFERENCE, HORIZON = 0.5, 0.5, 4.75


def relay_lcs():
    A = np.zeros((3, 3))
    A[0, 0], A[0, 1] = -1.0, 1.0
    B, C = np.zeros((3, 1)), np.zeros((1, 3))
    B[0, 0] = C[0, 0] = 1.0
    return dvi.Lcs(A=A, B=B, C=C, D=np.zeros((1, 1)), p=[0.0, 0.0, 1.0])


def relay_event():
    return dvi.UserEvent(lambda t, x, u: x[2] - T, direction="rising", action="modify",
                         modify=lambda t, x: [x[0], 1.0 if x[0] < REFERENCE else -1.0, 0.0])


def relay_exact():
    """v at each sampling time and s over each period."""
    v, s = [0.2], [1.0]
    for _ in range(1, int(HORIZON / T) + 1):
        v.append(max(0.0, s[-1] + (v[-1] - s[-1]) * math.exp(-T)))
        s.append(1.0 if v[-1] < REFERENCE else -1.0)
    return v, s


def relay_v(v, s, t):
    k = min(int(t / T), len(v) - 1)
    return max(0.0, s[k] + (v[k] - s[k]) * math.exp(-(t - k * T)))


def test_sampled_data_relay_controller_matches_its_exact_piecewise_solution():
    v, s = relay_exact()
    assert -1.0 in s  # the controller clamps the diode in some periods
    run = dvi.integrate_event(relay_lcs(), [0.2, 1.0, 0.0], 0.0, HORIZON, rtol=RTOL, atol=ATOL,
                              events=[relay_event()])
    assert run.succeeded, run.message
    user_times = [time for time, kind, _ in run.events if kind == "user"]
    assert len(user_times) == 9
    for k, time in enumerate(user_times, start=1):
        assert abs(time - k * T) <= EVENT_TIME_ERROR
    # At a sampling time the rows hold x⁻, then x⁺: the same v.
    errors = [abs(x[0] - relay_v(v, s, t)) for t, x in zip(run.times, run.states)]
    assert max(errors) <= STATE_ERROR
    assert len(run.events) > 9  # the diode's mode changes too

    # The stepper runs the same loop: advance_to(t_end) is the one-shot run.
    integrator = dvi.EventDrivenIntegrator(relay_lcs(), [0.2, 1.0, 0.0], 0.0, HORIZON,
                                           rtol=RTOL, atol=ATOL, events=[relay_event()])
    assert integrator.advance_to(HORIZON) == dvi.StepOutcome.END
    stepped = integrator.trajectory()
    np.testing.assert_array_equal(stepped.times, run.times)
    np.testing.assert_array_equal(stepped.states, run.states)


class Boom(Exception):
    pass


def raise_boom(*_):
    raise Boom("boom in a callback")


@pytest.mark.parametrize("keywords", [
    dict(observer=lambda obs: raise_boom() if obs.t > 0.5 else None),
    dict(events=[dvi.UserEvent(lambda t, x, u: raise_boom() if t > 0.5 else x[0] - 2)]),
    dict(events=[dvi.UserEvent(lambda t, x, u: x[0] - 0.5, direction="falling",
                               action="modify", modify=raise_boom)]),
], ids=["observer", "g", "modify"])
@pytest.mark.parametrize("problem", [diode(), callable_diode()], ids=["lcs", "callables"])
def test_a_callbacks_exception_reaches_the_caller_as_itself(keywords, problem):
    with pytest.raises(Boom, match="boom in a callback"):
        dvi.integrate_event(problem, [1.0], 0.0, 2.0, **keywords)
    integrator = dvi.EventDrivenIntegrator(problem, [1.0], 0.0, 2.0, **keywords)
    with pytest.raises(Boom, match="boom in a callback"):
        integrator.advance_to(2.0)
    # The run ends there: later calls name the exception.
    with pytest.raises(ValueError, match="a callable raised Boom: boom in a callback in an "
                                         "earlier call"):
        integrator.step()


def test_an_observer_raising_at_the_start_reaches_the_constructor():
    with pytest.raises(Boom):
        dvi.EventDrivenIntegrator(diode(), [1.0], 0.0, 2.0, observer=raise_boom)


def test_bad_observers_and_events_are_named():
    def run(**keywords):
        return dvi.integrate_event(diode(), [1.0], 0.0, 2.0, **keywords)

    with pytest.raises(dvi.InvalidInputError, match="integrate_event: observer must be a callable"):
        run(observer=3)
    with pytest.raises(dvi.InvalidInputError,
                       match=r"integrate_event: observer returned 7; expected None, a bool"):
        run(observer=lambda obs: 7)
    with pytest.raises(dvi.InvalidInputError, match=r"observer returned 'halt'"):
        run(observer=lambda obs: "halt")
    with pytest.raises(dvi.InvalidInputError,
                       match="integrate_event: events must be a list of dvi.UserEvent"):
        run(events=dvi.UserEvent(lambda t, x, u: x[0]))
    with pytest.raises(dvi.InvalidInputError,
                       match=r"integrate_event: events\[0\] is \{'g'.*not a dvi.UserEvent"):
        run(events=[{"g": lambda t, x, u: x[0]}])
    with pytest.raises(dvi.InvalidInputError,
                       match=r"integrate_event: events\[0\].g returned \[1.0\]; expected a number"):
        run(events=[dvi.UserEvent(lambda t, x, u: [1.0])])
    with pytest.raises(dvi.InvalidInputError,
                       match=r"EventDrivenIntegrator: events\[1\].g is NaN at t = 0.0"):
        dvi.EventDrivenIntegrator(diode(), [1.0], 0.0, 2.0, events=[
            dvi.UserEvent(lambda t, x, u: 1.0), dvi.UserEvent(lambda t, x, u: math.nan)]
        ).advance_to(2.0)
    halve = dict(direction="falling", action="modify")
    with pytest.raises(dvi.InvalidInputError,
                       match=r"integrate_event: events\[0\].modify returned 2 entries at t = "
                             r"0.2876.*, expected 1"):
        run(events=[dvi.UserEvent(lambda t, x, u: x[0] - 0.5, **halve,
                                  modify=lambda t, x: [0.0, 0.0])])
    with pytest.raises(dvi.InvalidInputError,
                       match=r"events\[0\].modify returned x\[0\] = inf at t = 0.2876.*: "
                             r"not finite"):
        run(events=[dvi.UserEvent(lambda t, x, u: x[0] - 0.5, **halve,
                                  modify=lambda t, x: [math.inf])])
    with pytest.raises(dvi.InvalidInputError, match="UserEvent: direction: unknown value \"up\""):
        dvi.UserEvent(lambda t, x, u: x[0], direction="up")
    with pytest.raises(dvi.InvalidInputError, match="UserEvent: action: unknown value \"reset\""):
        dvi.UserEvent(lambda t, x, u: x[0], action="reset")
    with pytest.raises(dvi.InvalidInputError, match="UserEvent: action \"modify\" needs modify="):
        dvi.UserEvent(lambda t, x, u: x[0], action="modify")
    with pytest.raises(dvi.InvalidInputError, match="UserEvent: modify is given but action is"):
        dvi.UserEvent(lambda t, x, u: x[0], modify=lambda t, x: x)


def test_observed_lcs_runs_hold_the_gil_in_threads():
    """An observed Lcs run keeps the GIL (its observer is Python): two
    threads integrating at once each see their own whole run."""
    import threading

    counts, runs = [[], []], [None, None]

    def work(k):
        runs[k] = dvi.integrate_event(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL,
                                      observer=lambda obs: counts[k].append(obs.t))

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for k in range(2):
        assert runs[k].succeeded and counts[k] == list(runs[k].times)



# The C++ tests' linear relay (tests/support/sampled_data_relay.hpp):
# v' = s + u, 0 <= u ⊥ v >= 0, s' = 0, τ' = 1; every T the event resets
# τ = 0 and sets s = +1 if v < 0.45, else -2. Backward Euler and CVODE are
# exact on its lines, in windows and event-driven intervals alike.
def linear_relay_lcs():
    A = np.zeros((3, 3))
    A[0, 1] = 1.0
    B, C = np.zeros((3, 1)), np.zeros((1, 3))
    B[0, 0] = C[0, 0] = 1.0
    return dvi.Lcs(A=A, B=B, C=C, D=np.zeros((1, 1)), p=[0.0, 0.0, 1.0])


def linear_relay_event():
    return dvi.UserEvent(lambda t, x, u: x[2] - T, direction="rising", action="modify",
                         modify=lambda t, x: [x[0], 1.0 if x[0] < 0.45 else -2.0, 0.0])


def linear_relay_v(t):
    v, s, start = 0.3, -2.0, 0.0
    while t > start + T:
        v = max(0.0, v + s * T)
        s = 1.0 if v < 0.45 else -2.0
        start += T
    return max(0.0, v + s * (t - start))


def test_auto_takes_observers_and_user_events():
    """integrate_auto: the stop event at ln(4/3), the observer seeing each
    row once; the relay run across time-stepping windows (event-driven runs
    of one CVODE step), its user events at kT; AutoIntegrator the same."""
    half = dvi.UserEvent(lambda t, x, u: x[0] - 0.5, direction="falling", action="stop")
    seen = []
    run = dvi.integrate_auto(diode(), [1.0], 0.0, 2.0, rtol=RTOL, atol=ATOL, events=[half],
                             observer=seen.append)
    assert run.status == "stopped-by-user" and "user event 0" in run.message
    assert abs(run.times[-1] - math.log(4 / 3)) <= EVENT_TIME_ERROR
    assert [obs.t for obs in seen] == list(run.times)

    windows = dict(rtol=1e-10, atol=1e-12, max_steps=1, h=0.04, stepping_window=0.02)
    x0 = [0.3, -2.0, 0.0]
    seen = []
    run = dvi.integrate_auto(linear_relay_lcs(), x0, 0.0, 2.3, **windows,
                             events=[linear_relay_event()], observer=seen.append)
    assert run.succeeded, run.message
    assert "stepping" in [interval["method"] for interval in run.intervals]
    user_times = [time for time, kind, _ in run.events if kind == "user"]
    assert len(user_times) == 4
    for k, time in enumerate(user_times, start=1):
        assert abs(time - k * T) <= EVENT_TIME_ERROR
    assert [obs.t for obs in seen] == list(run.times)
    assert max(abs(x[0] - linear_relay_v(t)) for t, x in zip(run.times, run.states)) <= 1e-10

    stepped_seen = []
    integrator = dvi.AutoIntegrator(linear_relay_lcs(), x0, 0.0, 2.3, **windows,
                                    events=[linear_relay_event()], observer=stepped_seen.append)
    assert integrator.advance_to(2.3) == dvi.StepOutcome.END
    np.testing.assert_array_equal(integrator.trajectory().times, run.times)
    assert [obs.t for obs in stepped_seen] == [obs.t for obs in seen]

    with pytest.raises(dvi.InvalidInputError, match="integrate_auto: observer must be a callable"):
        dvi.integrate_auto(diode(), [1.0], 0.0, 2.0, observer=3)


def disc_projection():
    """x = (p1, p2, s): p' = (1, 0), s' = u1, u = the projection of p onto
    the unit disc (u in SOL(K, u - p)): a K that is not a box, run on its
    KKT lifting. From p = (-2, 1/2), u2 = 1/(2|p|) outside the disc rises
    through 0.45 at t = 2 - sqrt(1/0.81 - 1/4) (the C++
    tests/nonbox_observer_test.cpp)."""
    return dvi.Dvi(n=3, m=2, f=lambda t, x, u: [1.0, 0.0, u[0]],
                   F=lambda t, x, u: np.asarray(u) - np.asarray(x[:2]),
                   K=dvi.ConvexSet.ball([0.0, 0.0], 1.0))


DISC_CROSSING = 2 - math.sqrt(1 / 0.81 - 0.25)


def disc_u(t):
    p = np.array([t - 2, 0.5])
    r = np.linalg.norm(p)
    return p / r if r > 1 else p


def test_observers_and_user_events_on_a_non_box_k_see_the_original_u():
    """Observer and g see u of K (2 entries, the exact projection), not the
    lifted multipliers; the stop is at the exact crossing, through
    integrate_event, EventDrivenIntegrator, integrate_auto and
    AutoIntegrator."""
    sizes = []

    def g(t, x, u):
        sizes.append(len(u))
        return u[1] - 0.45

    def check(run, seen):
        assert run.status == "stopped-by-user", run.message
        assert abs(run.times[-1] - DISC_CROSSING) <= EVENT_TIME_ERROR
        assert run.multipliers.shape[1] == 2
        assert set(sizes) == {2}
        assert seen and all(len(obs.u) == 2 for obs in seen)
        for obs in seen:
            if abs(np.linalg.norm([obs.t - 2, 0.5]) - 1) > 1e-8:
                assert np.max(np.abs(obs.u - disc_u(obs.t))) <= 1e-8, obs.t

    x0 = [-2.0, 0.5, 0.0]
    keywords = dict(rtol=RTOL, atol=ATOL)
    for integrate in (dvi.integrate_event, dvi.integrate_auto):
        seen, sizes[:] = [], []
        event = dvi.UserEvent(g, direction="rising", action="stop")
        run = integrate(disc_projection(), x0, 0.0, 4.0, **keywords, events=[event],
                        observer=seen.append)
        check(run, seen)
    for Integrator in (dvi.EventDrivenIntegrator, dvi.AutoIntegrator):
        seen, sizes[:] = [], []
        event = dvi.UserEvent(g, direction="rising", action="stop")
        integrator = Integrator(disc_projection(), x0, 0.0, 4.0, **keywords, events=[event],
                                observer=seen.append)
        assert integrator.advance_to(4.0) == dvi.StepOutcome.USER_STOP
        check(integrator.trajectory(), seen)
        assert len(integrator.u) == 2
