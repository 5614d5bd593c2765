#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Mutation soak of `dvisim run` over the example scenes (issue 28).

Each run takes an example scene, applies 1-4 structure-aware mutations
(numbers to extremes, strings and expressions spliced with hostile tokens,
fields dropped, added or retyped, arrays grown or emptied, the method
switched), runs the built dvisim on it in a scratch directory with
--max-wall, and checks the contract of `dvisim run`:

  exit 0 with trajectory.csv (every field a finite number, >= 2 rows) and a
  summary.json of status success; or exit 1 or 2 with a message on stderr
  and no file left in the scratch directory.

A signal or an exit code outside 0-2 is a crash, a run still going after
--timeout seconds a hang (--max-wall ends runs cleanly long before), and
anything else against the contract a breach; each is saved under
--findings. Prints the counts at the end; exits 1 on any finding.

    python3 tests/fuzz/mutate_scenes.py build/src/dvisim/dvisim --minutes 15
"""

import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

EXTREME_NUMBERS = [0, -0.0, 1, -1, 0.5, 2, 1e-12, -1e-12, 1e12, -1e12, 1e300, -1e300, 1e308,
                   -1e308, 1.7976931348623157e308, 5e-324, 1e-310, 1e-100, 1e-200, 2**31,
                   2**53 + 1, 10**20, 3, 1000, 1e6, -1e6, 0.999999, 1.000001]
SPECIAL_STRINGS = ["inf", "-inf", "nan", "", " ", "x1", "u1", "t", "pi", "1e400", "orthant",
                   "auto", "stepping", "event", "bdf", "adams", "klu", "dense", "7.2", "3.3",
                   "3.4", "7.3", "lemke", "pgs", "newton", "kkt", "extragradient"]
EXPRESSION_TOKENS = ["sin(", "cos(", "exp(", "log(", "sqrt(", "abs(", "sign(", "min(", "max(",
                     "tan(", "tanh(", "asin(", "factorial(", "tgamma(", ")", "(", ",", "^",
                     "^-", "0^", "*", "/", "+", "-", "--", "x1", "x2", "x3", "u1", "u2", "t",
                     "pi", "1e400", "5e-324", "1e-310", "1e308", "0", "0.0", "1.e", ".",
                     "10^(10^10)", "2^(10^30)", "2^(10^9)", "factorial(100000000)",
                     "binomial(100000000, 50000000)", "abs()", "sin()", "sqrt(-1)", "log(0)",
                     "1/0", "(x1 - x1)", "x1^2^3", "{x1}", "I", "y", "a", "(" * 40, ")" * 40]
HOSTILE_EXPRESSIONS = ["sin()", "exp()", "0^x1", "(sin(0))^t", "10^(10^10)", "2^(10^30)",
                       "factorial(100000000)", "binomial(100000000, 50000000)", "tgamma(x1)",
                       "2^(10^9)", "1/(x1 - x1)", "log(x1 - x1)", "x1^1e30", "exp(x1^2)*1e300",
                       "(((x1 + x1)^100)^100)^100", "x1^2", "-x1^3", "1e308*x1", "5e-324*x1",
                       "sqrt(x1)", "log(x1)", "1/x1", "tan(x1)", "asin(x1)"]
NAMES = ["name", "description", "problem", "x0", "horizon", "method", "output", "type", "A",
         "B", "C", "D", "p", "q", "f", "F", "f0", "f1", "h", "set", "params", "box", "lower",
         "upper", "polyhedron", "G", "E", "e", "ball", "center", "radius", "product", "sparse",
         "theta", "gamma", "rtol", "atol", "scheme", "adaptive", "h_max", "max_steps", "solver",
         "tol", "ode", "linear_solver", "max_events", "stepping_window", "max_handovers",
         "max_wall", "dir", "times", "samples", "plot", "boundary", "extra"]


def paths(value, prefix=()):
    """Every path into a JSON value, the root included."""
    yield prefix
    if isinstance(value, dict):
        for key, item in value.items():
            yield from paths(item, prefix + (key,))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from paths(item, prefix + (index,))


def get(value, path):
    for step in path:
        value = value[step]
    return value


def put(root, path, new):
    if not path:
        return new
    get(root, path[:-1])[path[-1]] = new
    return root


def mutate_string(text, rng):
    choice = rng.random()
    if choice < 0.3:
        return rng.choice(HOSTILE_EXPRESSIONS)
    if choice < 0.4:
        return rng.choice(SPECIAL_STRINGS)
    position = rng.randint(0, len(text))
    if choice < 0.8:
        return text[:position] + rng.choice(EXPRESSION_TOKENS) + text[position:]
    end = rng.randint(position, len(text))
    return text[:position] + text[end:]


def mutate_number(number, rng):
    choice = rng.random()
    if choice < 0.5:
        return rng.choice(EXTREME_NUMBERS)
    if choice < 0.8:
        return number * 10.0 ** rng.randint(-8, 8)
    if choice < 0.9:
        return -number
    return rng.choice(["inf", "-inf", "1", None, True, [number]])


def mutate_once(scene, rng):
    path = rng.choice(list(paths(scene)))
    value = get(scene, path)
    choice = rng.random()
    if isinstance(value, bool):
        return put(scene, path, rng.choice([not value, 1, "true", None]))
    if isinstance(value, (int, float)) and choice < 0.85:
        return put(scene, path, mutate_number(value, rng))
    if isinstance(value, str) and choice < 0.85:
        return put(scene, path, mutate_string(value, rng))
    if isinstance(value, list) and choice < 0.7:
        action = rng.random()
        if action < 0.3 and value:
            value.append(json.loads(json.dumps(rng.choice(value))))
        elif action < 0.55 and value:
            del value[rng.randrange(len(value))]
        elif action < 0.7:
            value.clear()
        elif action < 0.85 and value:
            rng.shuffle(value)
        else:
            value.append(rng.choice(EXTREME_NUMBERS + SPECIAL_STRINGS))
        return scene
    if isinstance(value, dict) and choice < 0.7:
        action = rng.random()
        if action < 0.45 and value:
            del value[rng.choice(list(value))]
        elif action < 0.75:
            value[rng.choice(NAMES)] = rng.choice(
                EXTREME_NUMBERS + SPECIAL_STRINGS + [None, [], {}, [1, 2], {"box": {}}])
        elif "method" in value or path == ():
            value["method"] = rng.choice(["auto", "stepping", "event",
                                          {"name": rng.choice(["auto", "stepping", "event"])}])
        return scene
    # Change the type of whatever is there.
    return put(scene, path, rng.choice([None, 0, "x", [], {}, [value], {"x": value}]))


def finite_csv(path):
    """Whether trajectory.csv has >= 2 rows after its header, every field finite."""
    with open(path) as csv:
        lines = csv.read().splitlines()
    if len(lines) < 3:
        return False
    for line in lines[1:]:
        for field in line.split(","):
            try:
                if not math.isfinite(float(field)):
                    return False
            except ValueError:
                return False
    return True


def listing(directory):
    return sorted(os.path.relpath(os.path.join(base, name), directory)
                  for base, dirs, files in os.walk(directory) for name in dirs + files)


def run_one(dvisim, text, max_wall, timeout):
    """Runs dvisim on the scene text; returns (outcome, detail)."""
    scratch = tempfile.mkdtemp(prefix="dvisim_mutation_")
    try:
        scene_path = os.path.join(scratch, "scene.json")
        with open(scene_path, "w") as scene_file:
            scene_file.write(text)
        command = [dvisim, "run", "scene.json", "--out", "out", "--max-wall", str(max_wall)]
        try:
            done = subprocess.run(command, cwd=scratch, capture_output=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return "hang", f"still running after {timeout} s"
        stderr = done.stderr.decode(errors="replace")
        code = done.returncode
        if code not in (0, 1, 2):
            return "crash", f"exit {code}: {stderr[-500:]}"
        if code == 0:
            csv = os.path.join(scratch, "out", "trajectory.csv")
            summary = os.path.join(scratch, "out", "summary.json")
            if not (os.path.exists(csv) and os.path.exists(summary)):
                return "breach", "exit 0 without trajectory.csv and summary.json"
            if json.load(open(summary)).get("status") != "success":
                return "breach", "exit 0 with a summary that is not success"
            if not finite_csv(csv):
                return "breach", "exit 0 with a non-finite or short trajectory.csv"
            return "exit 0", ""
        if not stderr.startswith("dvisim:"):
            return "breach", f"exit {code} without a message: {stderr[:200]!r}"
        left = listing(scratch)
        if left != ["scene.json"]:
            return "breach", f"exit {code} left files: {left}"
        if "max-wall" in stderr:
            return "max-wall", ""
        return f"exit {code}", ""
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dvisim", help="the built dvisim")
    parser.add_argument("--scenes", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "scenes"))
    parser.add_argument("--minutes", type=float, default=15)
    parser.add_argument("--seed", type=int, default=28)
    parser.add_argument("--max-wall", type=float, default=10,
                        help="dvisim's own --max-wall per run (s)")
    parser.add_argument("--timeout", type=float, default=60,
                        help="a run still going after this many seconds hangs")
    parser.add_argument("--findings", default="mutation-findings")
    args = parser.parse_args()
    args.dvisim = os.path.abspath(args.dvisim)

    rng = random.Random(args.seed)
    examples = []
    for name in sorted(os.listdir(args.scenes)):
        if name.endswith(".json"):
            with open(os.path.join(args.scenes, name)) as scene_file:
                examples.append((name, json.load(scene_file)))
    counts = {}
    findings = 0
    slowest = (0.0, "")
    start = time.monotonic()
    runs = 0
    while time.monotonic() - start < args.minutes * 60:
        name, example = rng.choice(examples)
        scene = json.loads(json.dumps(example))
        if isinstance(scene.get("output"), dict):
            scene["output"].pop("plot", None)  # gnuplot's time, not dvisim's
        for _ in range(rng.randint(1, 4)):
            scene = mutate_once(scene, rng)
        text = json.dumps(scene) if rng.random() < 0.97 else json.dumps(scene)[:-rng.randint(1, 9)]
        began = time.monotonic()
        outcome, detail = run_one(args.dvisim, text, args.max_wall, args.timeout)
        took = time.monotonic() - began
        slowest = max(slowest, (took, name))
        runs += 1
        counts[outcome] = counts.get(outcome, 0) + 1
        if outcome in ("crash", "hang", "breach"):
            findings += 1
            os.makedirs(args.findings, exist_ok=True)
            stem = os.path.join(args.findings, f"{outcome}-{runs:06d}-{name}")
            with open(stem, "w") as saved:
                saved.write(text)
            print(f"{outcome}: {detail} (saved {stem})", flush=True)
    elapsed = time.monotonic() - start
    print(f"{runs} runs in {elapsed:.0f} s ({runs / elapsed:.1f}/s), seed {args.seed}; slowest "
          f"{slowest[0]:.1f} s (from {slowest[1]})")
    for outcome in sorted(counts):
        print(f"  {outcome}: {counts[outcome]}")
    print(f"crashes {counts.get('crash', 0)}, hangs {counts.get('hang', 0)}, "
          f"contract breaches {counts.get('breach', 0)}")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
