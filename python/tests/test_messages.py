# SPDX-License-Identifier: Apache-2.0
"""Bad arguments from Python raise messages in Python's names (issue 33):
the function called, the keyword, method and index as the caller wrote
them (integrate_auto: rtol, solver_tolerance, advance_to, x0[0]), never
the C++ names the library's own messages use for C++ callers
(AutoOptions.event.rtol, SolverOptions::tolerance, AdvanceTo, x0(0))."""
import math
import re

import numpy as np
import pytest

import dvi

# What only a C++ caller writes.
CXX_NAMES = re.compile(r"::|AutoOptions|SolverOptions|options\.|Integrate[A-Z]|AdvanceTo|Reinit|"
                       r"StateAt|FilippovSystem|Box:|atol_per_state|\w\(\d+\)|t\(\)")


def diode():
    one = np.ones((1, 1))
    return dvi.Lcs(A=-one, B=one, C=one, D=0 * one, p=[-1.0])


def stepper_at_half():
    integrator = dvi.EventDrivenIntegrator(diode(), [1.0], 0.0, 2.0)
    integrator.advance_to(0.5)
    return integrator


def saturation(**keywords):
    return dvi.Dvi(n=1, m=1, f=lambda t, x, u: u, F=lambda t, x, u: u + x,
                   K=dvi.ConvexSet.box([-1.0], [1.0]), **keywords)


CASES = [
    # integrate_auto's options: AutoOptions.event.*, AutoOptions.stepping.*, AutoOptions.*
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, rtol=-1),
     r"integrate_auto: rtol, atol: -1, 1e-10 must be finite"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, max_events=0),
     r"integrate_auto: max_events: 0 is not positive"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, output_times=[0.5, 0.2]),
     r"integrate_auto: output_times\[1\]: 0.2 is below output_times\[0\] = 0.5"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, h=-1),
     r"integrate_auto: h: -1 is not a positive step size"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, theta=2),
     r"integrate_auto: theta: 2 is outside \[0, 1\]"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, stepping_window=2),
     r"integrate_auto: stepping_window: 2 is outside \(0, 1\]"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, max_handovers=0),
     r"integrate_auto: max_handovers: 0 is not positive"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, window_rtol=2),
     r"integrate_auto: window_rtol: 2 is outside \[0, 1\)"),
    # SolverOptions::tolerance, ::max_iterations: the solver_* keywords
    (lambda: dvi.integrate_event(diode(), [1.0], 0, 1, solver_tolerance=2),
     r"integrate_event: solver_tolerance: 2 is outside \(0, 1\)"),
    (lambda: dvi.integrate_stepping(diode(), [1.0], 0, 1, solver_max_iterations=-1),
     r"integrate_stepping: solver_max_iterations: -1 is negative"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, solver_tolerance=2),
     r"integrate_auto: solver_tolerance: 2 is outside \(0, 1\)"),
    (lambda: dvi.EventDrivenIntegrator(diode(), [1.0], 0, 1, solver_tolerance=0),
     r"EventDrivenIntegrator: solver_tolerance: 0 is outside \(0, 1\)"),
    # ... but solve's keywords are tolerance and max_iterations
    (lambda: dvi.solve(dvi.Lcp(np.eye(1), [1.0]), tolerance=5),
     r"solve: tolerance: 5 is outside \(0, 1\)"),
    (lambda: dvi.solve(dvi.Lcp(np.eye(1), [1.0]), max_iterations=-1),
     r"solve: max_iterations: -1 is negative"),
    # atol_per_state[i] is atol's entry i; Eigen's x0(i) is numpy's x0[i]
    (lambda: dvi.integrate_event(diode(), [1.0], 0, 1, atol=[math.nan]),
     r"integrate_event: atol\[0\]: nan must be finite"),
    (lambda: dvi.integrate_auto(diode(), [1.0], 0, 1, atol=[-1.0]),
     r"integrate_auto: atol\[0\]: -1 must be finite"),
    (lambda: dvi.integrate_event(diode(), [math.nan], 0, 1),
     r"integrate_event: x0\[0\] = nan is not finite"),
    (lambda: dvi.integrate_ida(diode(), [1.0], 0, -1),
     r"integrate_ida: t0, t_end: 0, -1 must be finite with t_end > t0"),
    # the stepper: its keywords, its methods, IntegrateEventDriven
    (lambda: dvi.EventDrivenIntegrator(saturation(), [3.0], 0, 1, output_times=[0.5, 2.0]),
     r"EventDrivenIntegrator: output_times\[1\]: 2 is outside \[t0, t_end\] = \[0, 1\]"),
    (lambda: dvi.AutoIntegrator(diode(), [1.0], 0, 1, h=-1),
     r"AutoIntegrator: h: -1 is not a positive step size"),
    (lambda: stepper_at_half().advance_to(0.25),
     r"advance_to: t = 0.25 is before the current time 0.5"),
    (lambda: stepper_at_half().reinit(0.25, [1.0]),
     r"reinit: t = 0.25 must be finite, in \[t = 0.5, t_end = 2\)"),
    (lambda: stepper_at_half().reinit(0.5, [math.inf]),
     r"reinit: x\[0\] = inf is not finite"),
    (lambda: stepper_at_half().state_at(0.0),
     r"state_at: t = 0 is outside the last step of the current mode.*"
     r"\(trajectory\(\).state_at interpolates the samples\)"),
    # problems: the Python class names and indices
    (lambda: dvi.Filippov(n=0, k=1, f0=lambda t, x: [0.0], f1=lambda t, x: [[1.0]],
                          h=lambda t, x: [x[0]]),
     r"Filippov.n: 0 is not a positive state dimension"),
    (lambda: dvi.ConvexSet.box([1.0], [0.0]),
     r"ConvexSet.box: lower\[0\] = 1 exceeds upper\[0\] = 0"),
]


@pytest.mark.parametrize("call, message", CASES, ids=[c[1][:40] for c in CASES])
def test_bad_arguments_are_named_as_python_calls_them(call, message):
    with pytest.raises(dvi.InvalidInputError) as raised:
        call()
    text = str(raised.value)
    assert re.search(message, text), text
    assert not CXX_NAMES.search(text), text
