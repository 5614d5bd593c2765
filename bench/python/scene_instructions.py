# SPDX-License-Identifier: Apache-2.0
"""A scene's run from Python (dvi.Scene: from_json, run, csv, summary)
against `dvisim run` of the same scene, in instructions (valgrind's
callgrind; wall clock means little on a shared machine). Each side's
start-up is taken off: Python's by the difference between 1 and 1 + RUNS
runs in one interpreter, dvisim's by `dvisim --version`. dvisim also writes
its files (and a plot where the scene asks for one); Python builds the same
texts but writes nothing. Usage (after building):

    PYTHONPATH=build/python /usr/bin/python3 bench/python/scene_instructions.py build
"""
import os
import re
import subprocess
import sys
import tempfile

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RUNS = 4
SCENES = [("diode_bridge.json", {}), ("dvi_saturation.json", {}),
          ("dvi_saturation.json", {"method": "event"})]


def instructions(command):
    """Instructions the command executes (callgrind's Ir), its children included."""
    done = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                           "--trace-children=yes", *command],
                          capture_output=True, text=True, check=True, env=os.environ)
    return sum(int(n.replace(",", "")) for n in re.findall(r"Collected : ([\d,]+)", done.stderr))


def python_runs(path, keywords, runs):
    script = (f"import dvi\nscene = dvi.Scene.from_json({path!r})\n"
              f"for _ in range({runs}):\n"
              f"    run = dvi.Scene.from_json({path!r}).run(**{keywords!r})\n"
              f"    assert run.trajectory.succeeded and run.csv and run.summary\n")
    return instructions([sys.executable, "-c", script])


def main():
    dvisim = os.path.join(BUILD, "src/dvisim/dvisim")
    start_up = instructions([dvisim, "--version"])
    print(f"instructions per scene run (callgrind), start-ups taken off; {RUNS} Python runs:")
    for name, keywords in SCENES:
        path = os.path.join(SOURCE, "examples/scenes", name)
        python = (python_runs(path, keywords, 1 + RUNS) - python_runs(path, keywords, 1)) / RUNS
        flags = [f"--{k}={v}" for k, v in keywords.items()]
        with tempfile.TemporaryDirectory() as out:
            process = instructions([dvisim, "run", path, "--out", out, *flags]) - start_up
        label = f"{name} {' '.join(flags) or '(its method)'}"
        print(f"  {label}: Python {python / 1e6:.1f} M, dvisim {process / 1e6:.1f} M, "
              f"Python / dvisim {python / process:.2f}")


if __name__ == "__main__":
    main()
