# SPDX-License-Identifier: Apache-2.0
"""Python's cost (issue 33): the bindings on an Lcs (no callables) against
the run's own time, advance_to from Python against AdvanceTo from C++, and
a DVI of Python callables against the same DVI as C++ functors and as scene
expressions. Usage (after building):

    PYTHONPATH=build/python /usr/bin/python3 bench/python/python_overhead.py build
"""
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import dvi

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
REPEATS = 5


def median(values):
    return statistics.median(values)


def diode_bridge():
    scene = json.load(open(os.path.join(SOURCE, "examples/scenes/diode_bridge.json")))
    p = scene["problem"]
    return dvi.Lcs(A=np.array(p["A"]), B=np.array(p["B"]), C=np.array(p["C"]),
                   D=np.array(p["D"])), scene["x0"], scene["horizon"]


def bindings_overhead():
    """The whole Python call (arguments, run, result arrays) against the run's
    own wall time, measured inside C++."""
    lcs, x0, horizon = diode_bridge()
    times = list(np.linspace(0, horizon, 1001))
    ratios, own = [], []
    for _ in range(REPEATS):
        start = time.perf_counter()
        run = dvi.integrate_auto(lcs, x0, 0.0, horizon, output_times=times)
        states, multipliers = run.states, run.multipliers  # the arrays a user reads
        total = time.perf_counter() - start
        assert run.succeeded and states.shape[0] >= 1001 and multipliers.shape[1] == 4
        own.append(run.stats["wall_seconds"])
        ratios.append(total / run.stats["wall_seconds"] - 1)
    return median(own), median(ratios)


STOPS = (100, 1000, 10000)


def stepper_overhead():
    """advance_to from Python against AdvanceTo from C++ (advance_to_cxx): the
    diode bridge on an EventDrivenIntegrator, advanced to t_end in N equal
    calls, construction included; CPU seconds (medians), the same steps and
    final state on both sides."""
    lcs, x0, horizon = diode_bridge()
    cxx = json.loads(subprocess.run([os.path.join(BUILD, "bench/advance_to_cxx"),
                                     *map(str, STOPS)], check=True, capture_output=True,
                                    text=True).stdout)
    rows = []
    for stops in STOPS:
        cpu = []
        for run in range(REPEATS + 1):  # the first untimed, as TimeRuns
            start = time.process_time()
            integrator = dvi.EventDrivenIntegrator(lcs, x0, 0.0, horizon, ode="adams")
            for k in range(1, stops + 1):
                integrator.advance_to(horizon * k / stops)
            final, steps = integrator.x, integrator.stats["steps"]
            if run:
                cpu.append(time.process_time() - start)
        reference = cxx[str(stops)]
        assert steps == reference["steps"] and list(final) == reference["final"], (stops, final)
        rows.append((stops, steps, reference["cpu"], median(cpu)))
    return rows


def saturation_python():
    return dvi.Dvi(n=1, m=1, f=lambda t, x, u: u, F=lambda t, x, u: u + x,
                   K=dvi.ConvexSet.box([-1.0], [1.0]),
                   f_jacobian=lambda t, x, u: (np.zeros((1, 1)), np.ones((1, 1))),
                   F_jacobian=lambda t, x, u: (np.ones((1, 1)), np.ones((1, 1))))


def callables_against_cxx_and_scene():
    problem = saturation_python()
    python = {
        "stepping": median([dvi.integrate_stepping(problem, [3.0], 0.0, 4.0, h=1e-3)
                            .stats["wall_seconds"] for _ in range(REPEATS)]),
        "event": median([dvi.integrate_event(problem, [3.0], 0.0, 4.0, rtol=1e-10, atol=1e-12)
                         .stats["wall_seconds"] for _ in range(REPEATS)]),
    }
    cxx = json.loads(subprocess.run([os.path.join(BUILD, "bench/saturation_cxx")], check=True,
                                    capture_output=True, text=True).stdout)
    scene_seconds = []
    with tempfile.TemporaryDirectory() as out:
        for _ in range(REPEATS):
            subprocess.run([os.path.join(BUILD, "src/dvisim/dvisim"), "run",
                            os.path.join(SOURCE, "examples/scenes/dvi_saturation.json"),
                            "--out", out, "--method", "stepping"], check=True,
                           capture_output=True)
            scene_seconds.append(json.load(open(os.path.join(out, "summary.json")))
                                 ["stats"]["wall_seconds"])
    return python, cxx, median(scene_seconds)


def cpu_seconds(who):
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def scene_against_dvisim(name, *flags):
    """A scene run from Python (Scene.from_json, run, its csv and summary:
    what dvisim computes before writing its files) against `dvisim run` of
    the same scene as a process (start, read, run, write): CPU seconds of
    each, and the integration's own wall time inside both."""
    path = os.path.join(SOURCE, "examples/scenes", name)
    keywords = {flags[k].lstrip("-"): flags[k + 1] for k in range(0, len(flags), 2)}
    python, python_own, process, process_own = [], [], [], []
    with tempfile.TemporaryDirectory() as out:
        for _ in range(REPEATS):
            start = cpu_seconds(resource.RUSAGE_SELF)
            run = dvi.Scene.from_json(path).run(**keywords)
            text, summary = run.csv, run.summary
            python.append(cpu_seconds(resource.RUSAGE_SELF) - start)
            python_own.append(run.trajectory.stats["wall_seconds"])
            assert run.trajectory.succeeded and text and summary
            start = cpu_seconds(resource.RUSAGE_CHILDREN)
            subprocess.run([os.path.join(BUILD, "src/dvisim/dvisim"), "run", path, "--out", out,
                            *flags], check=True, capture_output=True)
            process.append(cpu_seconds(resource.RUSAGE_CHILDREN) - start)
            process_own.append(json.load(open(os.path.join(out, "summary.json")))
                               ["stats"]["wall_seconds"])
    return median(python), median(python_own), median(process), median(process_own)


def main():
    own, ratio = bindings_overhead()
    print(f"diode bridge (auto, 1001 outputs): run {own * 1e3:.2f} ms, "
          f"bindings add {ratio * 100:.1f} %")
    print("diode bridge on dvi.EventDrivenIntegrator, N advance_to calls to t_end (CPU time):")
    for stops, steps, cxx_cpu, python_cpu in stepper_overhead():
        print(f"  N = {stops:5d} ({steps:5d} steps): C++ {cxx_cpu * 1e3:7.2f} ms, "
              f"Python {python_cpu * 1e3:7.2f} ms, {(python_cpu / cxx_cpu - 1) * 100:+6.1f} %, "
              f"{(python_cpu - cxx_cpu) / stops * 1e6:+.2f} us per call")
    python, cxx, scene = callables_against_cxx_and_scene()
    print("saturated decay, time-stepping h = 1e-3 over [0, 4] (4000 steps):")
    print(f"  C++ functors {cxx['stepping'] * 1e3:.2f} ms, scene expressions {scene * 1e3:.2f} ms, "
          f"Python callables {python['stepping'] * 1e3:.2f} ms "
          f"({python['stepping'] / cxx['stepping']:.1f}x C++)")
    print("saturated decay, event-driven rtol 1e-10:")
    print(f"  C++ functors {cxx['event'] * 1e3:.3f} ms, Python callables "
          f"{python['event'] * 1e3:.3f} ms ({python['event'] / cxx['event']:.1f}x C++)")
    print("scenes, dvi.Scene (from_json, run, csv, summary) against `dvisim run` (CPU time):")
    for name, flags in [("diode_bridge.json", ()), ("dvi_saturation.json", ()),
                        ("dvi_saturation.json", ("--method", "event"))]:
        python, python_own, process, process_own = scene_against_dvisim(name, *flags)
        print(f"  {name} {' '.join(flags) or '(its method)'}: Python {python * 1e3:.2f} ms "
              f"(run {python_own * 1e3:.2f} ms), dvisim {process * 1e3:.2f} ms "
              f"(run {process_own * 1e3:.2f} ms); Python - dvisim {(python - process) * 1e3:+.2f} ms")


if __name__ == "__main__":
    main()
