# SPDX-License-Identifier: Apache-2.0
"""What the bindings add, in instructions (valgrind's callgrind; wall clock
means little on a shared machine), issue 33's goal "the bindings add <= 5 %
to a diode-bridge run":

1. the one-shot run: dvi.integrate_event on the diode bridge (Adams, the
   scene's matrices), its states read, against one_shot_cxx's
   IntegrateEventDriven of the same circuit (the same steps and final state,
   checked); each side's start-up taken off (1 + RUNS runs minus 1, per run);
2. the floor of one pybind11 call (bench/python/call_floor.cpp: an empty
   function, an empty method taking a float, the same releasing the GIL)
   against dvi's own per-call costs (a property read, advance_to at the
   current time: no step), each over CALLS calls in a loop, the loop's own
   iteration taken off;
3. an observer's cost per observation: the one-shot run with
   observer=lambda obs: None against the run without, per observation.

    PYTHONPATH=build/python:build/bench/python /usr/bin/python3 bench/python/call_instructions.py build
"""
import json
import os
import subprocess
import sys

from scene_instructions import instructions

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(SOURCE, "examples/scenes/diode_bridge.json")
RUNS = 4
CALLS = 100_000
# Python's string hashes are salted per process, and dict probes with them:
# one seed makes the counts repeatable (they still move by tens per call).
os.environ["PYTHONHASHSEED"] = "0"

SETUP = (
    "import json\nimport numpy as np\nimport dvi\nimport call_floor\n"
    f"p = json.load(open({SCENE!r}))\n"
    "lcs = dvi.Lcs(A=np.array(p['problem']['A']), B=np.array(p['problem']['B']),\n"
    "              C=np.array(p['problem']['C']), D=np.array(p['problem']['D']))\n"
    "horizon = p['horizon']\n"
    "integrator = dvi.EventDrivenIntegrator(lcs, p['x0'], 0.0, horizon, ode='adams')\n"
    "integrator.advance_to(horizon / 10)\n"
    "now = integrator.t\n"
    "empty, thing = call_floor.empty, call_floor.Object()\n")

ONE_SHOT = ("run = dvi.integrate_event(lcs, p['x0'], 0.0, horizon, ode='adams')\n"
            "states = run.states\n")
OBSERVED = ("run = dvi.integrate_event(lcs, p['x0'], 0.0, horizon, ode='adams',\n"
            "                          observer=lambda obs: None)\n"
            "states = run.states\n")

BODIES = [
    ("empty()", "an empty bound function, no argument"),
    ("thing.take(now)", "an empty method taking a float"),
    ("thing.take_released(now)", "the same, releasing the GIL"),
    ("integrator.t", "dvi: a property read (integrator.t)"),
    ("integrator.advance_to(now)", "dvi: advance_to at the current t"),
]


def python(body, count):
    script = SETUP + f"for _ in range({count}):\n" + "".join(
        f"    {line}\n" for line in body.splitlines())
    return script


def per_loop(body, count, base=0):
    return (instructions([sys.executable, "-c", python(body, count)]) - base) / count


def check_same_run():
    cxx = json.loads(subprocess.run([os.path.join(BUILD, "bench/one_shot_cxx"), "1"],
                                    capture_output=True, text=True, check=True).stdout)
    script = python(ONE_SHOT, 1) + "print(json.dumps({'steps': run.stats['steps'], " \
                                   "'final': list(run.states[-1])}))\n"
    py = json.loads(subprocess.run([sys.executable, "-c", script], capture_output=True,
                                   text=True, check=True).stdout)
    assert py == cxx, (py, cxx)
    return cxx["steps"]


def dvi_observations():
    """How many observations the observed run makes."""
    script = python(OBSERVED.replace("lambda obs: None", "seen.append"), 1) + \
        "print(len(seen))\n"
    return int(subprocess.run([sys.executable, "-c", "seen = []\n" + script],
                              capture_output=True, text=True, check=True).stdout)


def main():
    steps = check_same_run()
    program = os.path.join(BUILD, "bench/one_shot_cxx")
    cxx = (instructions([program, str(1 + RUNS)]) - instructions([program, "1"])) / RUNS
    one = instructions([sys.executable, "-c", python(ONE_SHOT, 1)])
    py = (instructions([sys.executable, "-c", python(ONE_SHOT, 1 + RUNS)]) - one) / RUNS
    print(f"one-shot integrate_event, diode bridge ({steps} steps, the same final state):")
    print(f"  C++ {cxx / 1e6:.3f} M, Python {py / 1e6:.3f} M per run, bindings add "
          f"{(py / cxx - 1) * 100:+.2f} % ({py - cxx:+.0f} instructions)")
    observations = dvi_observations()
    observed = (instructions([sys.executable, "-c", python(OBSERVED, 1 + RUNS)]) -
                instructions([sys.executable, "-c", python(OBSERVED, 1)])) / RUNS
    print(f"  with observer=lambda obs: None ({observations} observations): "
          f"{(observed - py) / observations:.0f} per observation")
    start = instructions([sys.executable, "-c", python("pass", 0)])
    loop = per_loop("pass", CALLS, start)
    print(f"per call over {CALLS} calls (callgrind), the loop's iteration ({loop:.0f}) taken off:")
    for body, label in BODIES:
        print(f"  {label:42s} {per_loop(body, CALLS, start) - loop:6.0f}")


if __name__ == "__main__":
    main()
