# SPDX-License-Identifier: Apache-2.0
"""advance_to from Python against AdvanceTo from C++ in instructions
(valgrind's callgrind; wall clock means little on a shared machine): the
diode bridge on an EventDrivenIntegrator advanced to t_end in N equal calls,
as python_overhead.py times it. C++: advance_to_cxx N (1 + 7 loops) minus
advance_to_cxx alone (its start-up), per loop. Python: the loop 1 + RUNS
times minus once in one interpreter, per loop. Both take the same steps to
the same final state (python_overhead.py checks it). Usage (after building):

    PYTHONPATH=build/python /usr/bin/python3 bench/python/stepper_instructions.py build
"""
import os
import sys

from scene_instructions import instructions

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CXX_LOOPS = 8  # advance_to_cxx: one untimed run and 7 timed (bench/common TimeRuns)
RUNS = 2
STOPS = (100, 1000, 10000)


def python_loops(stops, loops):
    scene = os.path.join(SOURCE, "examples/scenes/diode_bridge.json")
    script = (
        "import json\nimport numpy as np\nimport dvi\n"
        f"p = json.load(open({scene!r}))\n"
        "lcs = dvi.Lcs(A=np.array(p['problem']['A']), B=np.array(p['problem']['B']),\n"
        "              C=np.array(p['problem']['C']), D=np.array(p['problem']['D']))\n"
        "horizon = p['horizon']\n"
        f"for _ in range({loops}):\n"
        "    integrator = dvi.EventDrivenIntegrator(lcs, p['x0'], 0.0, horizon, ode='adams')\n"
        f"    for k in range(1, {stops} + 1):\n"
        f"        integrator.advance_to(horizon * k / {stops})\n"
        "    final, steps = integrator.x, integrator.stats['steps']\n")
    return instructions([sys.executable, "-c", script])


def main():
    program = os.path.join(BUILD, "bench/advance_to_cxx")
    start_up = instructions([program])
    print(f"instructions per loop of N advance_to calls (callgrind), start-ups taken off:")
    for stops in STOPS:
        cxx = (instructions([program, str(stops)]) - start_up) / CXX_LOOPS
        python = (python_loops(stops, 1 + RUNS) - python_loops(stops, 1)) / RUNS
        print(f"  N = {stops:5d}: C++ {cxx / 1e6:7.2f} M, Python {python / 1e6:7.2f} M, "
              f"{(python / cxx - 1) * 100:+5.1f} %, {(python - cxx) / stops:+.0f} per call")


if __name__ == "__main__":
    main()
