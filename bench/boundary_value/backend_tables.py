# SPDX-License-Identifier: Apache-2.0
"""The tables of run_backend.sh (README.md, "The PETSc back-end").

Reads OUT_DIR/backend.jsonl (one line per run of boundary_value_bench), the
node-by-node dumps OUT_DIR/dump-COLUMN-PROBLEM-N.bin and the -log_view files
OUT_DIR/log_view-PROBLEM-N.txt, and prints markdown: the runs, the ratios and
the goal (PETSc on 1 rank within 1.5x of dvi serial at the largest N), the
answers' differences, where PETSc's time goes; and, when run_traffic.sh
wrote OUT_DIR/traffic.jsonl and OUT_DIR/log_view_mumps-*.txt, the 2-rank
traffic and the weak-scaling projection (projection()).
Usage: /usr/bin/python3 backend_tables.py OUT_DIR
"""
import array
import glob
import json
import os
import re
import sys

COLUMNS = ("dvi", "petsc1", "petsc2")
NAMES = {"dvi": "dvi serial", "petsc1": "PETSc 1 rank", "petsc2": "PETSc 2 ranks"}
GOAL = 1.5
# The projection's network (an assumption, not a measurement: 2 cores here):
# 100 Gb/s InfiniBand, about 10 GB/s and 2 µs a message.
BANDWIDTH = 10e9
LATENCY = 2e-6
RANKS = (2, 4, 16, 64, 256)
# -log_view events shown, in this order (PETSc 3.18's names).
EVENTS = ("SNESSolve", "SNESFunctionEval", "SNESJacobianEval", "SNESLineSearch", "KSPSolve",
          "PCSetUp", "MatLUFactorSym", "MatLUFactorNum", "MatSolve", "MatCreateSubMats",
          "MatAssemblyEnd", "VecScatterBegin", "SNESSetUp", "DMCreateMat")


def load_runs(out_dir):
    runs = {}
    with open(os.path.join(out_dir, "backend.jsonl")) as f:
        for line in f:
            line = line.strip()
            if line:
                run = json.loads(line)
                runs[(run["problem"], run["steps"], run["column"])] = run
    return runs


def ok(run):
    return run is not None and run.get("status") == "success"


def runs_table(runs):
    print("| problem | N | unknowns | run | wall s | CPU s | Newton its finest / all grids "
          "| F evals | J evals | peak RSS MB | load |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (problem, n, column), run in sorted(runs.items(), key=lambda kv: (
            kv[0][0] != "lcs", kv[0][1], COLUMNS.index(kv[0][2]))):
        if not ok(run):
            print(f"| {problem} | {n} | | {NAMES[column]} | FAILED ({run.get('status', '?')}) "
                  f"| | | | | {run['time_rss_mb']:.0f} | {run['load']} |")
            continue
        # Two ranks: /usr/bin/time's peak is the largest rank's; the bench
        # sums every rank's.
        rss = f"{run['time_rss_mb']:.0f}"
        if column == "petsc2":
            rss += f" (sum {run['peak_rss_mb']:.0f})"
        print(f"| {problem} | {n} | {run['unknowns']} | {NAMES[column]} | {run['seconds']:.4g} "
              f"| {run['cpu_seconds']:.4g} | {run['iterations']} / {run['total_iterations']} "
              f"| {run['rhs_evals']} | {run['jacobian_evals']} | {rss} | {run['load']} |")


def dump(out_dir, column, problem, n):
    path = os.path.join(out_dir, f"dump-{column}-{problem}-{n}.bin")
    if not os.path.exists(path):
        return None
    values = array.array("d")
    with open(path, "rb") as f:
        values.frombytes(f.read())
    return values


def max_difference(a, b):
    if a is None or b is None or len(a) != len(b):
        return None
    return max(abs(x - y) for x, y in zip(a, b))


def ratio_table(runs):
    print("| problem | N | PETSc 1 rank / dvi serial, CPU (wall) | peak RSS, dvi → PETSc 1 rank MB "
          "| 2 ranks / 1 rank wall (speed-up) | max abs difference 1 vs 2 ranks | PETSc 1 rank vs dvi |")
    print("|---|---|---|---|---|---|---|")
    keys = sorted({(p, n) for p, n, _ in runs}, key=lambda k: (k[0] != "lcs", k[1]))
    for problem, n in keys:
        serial, one, two = (runs.get((problem, n, c)) for c in COLUMNS)
        cells = []
        if ok(serial) and ok(one):
            cells.append(f"{one['cpu_seconds'] / serial['cpu_seconds']:.2f} "
                         f"({one['seconds'] / serial['seconds']:.2f})")
            cells.append(f"{serial['time_rss_mb']:.0f} → {one['time_rss_mb']:.0f}")
        else:
            cells += ["-", "-"]
        cells.append(f"{two['seconds'] / one['seconds']:.2f} ({one['seconds'] / two['seconds']:.2f}×)"
                     if ok(one) and ok(two) else "-")
        dumps = {c: dump(OUT_DIR, c, problem, n) for c in COLUMNS}
        for a, b in (("petsc1", "petsc2"), ("dvi", "petsc1")):
            d = max_difference(dumps[a], dumps[b])
            cells.append("-" if d is None else f"{d:.2g}")
        print(f"| {problem} | {n} | " + " | ".join(cells) + " |")


def goal(runs):
    largest = max(n for _, n, _ in runs)
    print(f"Goal (issue 34): PETSc on 1 rank within {GOAL}× of the serial dvi solve at N = {largest}:")
    print()
    for problem in ("lcs", "game"):
        serial, one = runs.get((problem, largest, "dvi")), runs.get((problem, largest, "petsc1"))
        if not (ok(serial) and ok(one)):
            print(f"- {problem}: not measured")
            continue
        cpu = one["cpu_seconds"] / serial["cpu_seconds"]
        wall = one["seconds"] / serial["seconds"]
        verdict = "PASS" if max(cpu, wall) <= GOAL else "FAIL"
        print(f"- {problem}: CPU {cpu:.2f}×, wall {wall:.2f}× (load {serial['load']} / {one['load']}): "
              f"{verdict}")


def log_view(path):
    """{event: (count, seconds)} of a -log_view file (the Max columns)."""
    events = {}
    with open(path) as f:
        for line in f:
            tokens = line.split()
            if len(tokens) > 4 and tokens[0] in EVENTS and re.fullmatch(r"\d+", tokens[1]):
                events.setdefault(tokens[0], (int(tokens[1]), float(tokens[3])))
    return events


def log_view_table(out_dir):
    files = sorted(glob.glob(os.path.join(out_dir, "log_view-*.txt")))
    if not files:
        return
    parsed = {}
    for path in files:
        name = os.path.basename(path)[len("log_view-"):-len(".txt")]
        parsed[name] = log_view(path)
    names = list(parsed)
    print("| PETSc event (1 rank) | " + " | ".join(f"{n}: count, s, % of SNESSolve" for n in names) + " |")
    print("|---|" + "---|" * len(names))
    for event in EVENTS:
        cells = []
        for name in names:
            count, seconds = parsed[name].get(event, (0, 0.0))
            total = parsed[name].get("SNESSolve", (0, 0.0))[1]
            share = f"{100 * seconds / total:.0f} %" if total > 0 else "-"
            cells.append(f"{count}, {seconds:.3g}, {share}")
        print(f"| {event} | " + " | ".join(cells) + " |")


def petsc_work(run):
    """Σ over the PETSc grids (all but the first, cold, dvi's) of
    iterations × unknowns, and the iterations: what the traffic and the
    time scale with."""
    per_step = run["unknowns"] / run["steps"]
    steps, its = run["grid_steps"][1:], run["grid_iterations"][1:]
    return sum(s * per_step * i for s, i in zip(steps, its)), sum(its)


def projection(out_dir):
    """Weak scaling to K ranks (n unknowns a rank, K·n in all) of one Newton
    iteration, from what 1 and 2 ranks show:
      T1 = t_seq + t_par on 1 rank with MUMPS, t_seq its analysis
      (MatLUFactorSym, sequential in MUMPS: on K ranks one rank's work on
      K·n unknowns, so K·t_seq), t_par the rest (stays t_par);
      communication β bytes per global unknown and iteration and μ messages
      per iteration (measured on 2 ranks), over the assumed network: at
      best every rank sends β·n (c = β·n/bandwidth + μ·latency), at worst
      all of it passes one rank (MUMPS's analysis and root: K·c).
      E(K) = T1 / (K·t_seq + t_par + c) at best, / (K·t_seq + t_par + K·c)."""
    path = os.path.join(out_dir, "traffic.jsonl")
    if not os.path.exists(path):
        return
    runs = {}
    with open(path) as f:
        for line in f:
            if line.strip():
                run = json.loads(line)
                runs.setdefault(run["problem"], []).append(run)
    print("| problem | N | PETSc grids' iterations | bytes between the 2 ranks, point-to-point / collectives "
          "| messages | bytes per unknown and iteration (difference of the two N) |")
    print("|---|---|---|---|---|---|")
    model = {}
    for problem, problem_runs in runs.items():
        problem_runs.sort(key=lambda r: r["steps"])
        beta = mu = None
        if len(problem_runs) >= 2:
            small, large = problem_runs[0], problem_runs[-1]
            (w0, i0), (w1, i1) = petsc_work(small), petsc_work(large)
            total = lambda r: r["p2p_bytes"] + r["collective_bytes"]
            messages = lambda r: r["p2p_messages"] + r["collective_messages"]
            beta = (total(large) - total(small)) / (w1 - w0)
            mu = messages(large) / max(i1, 1)
        for run in problem_runs:
            work, its = petsc_work(run)
            print(f"| {problem} | {run['steps']} | {its} | {run['p2p_bytes'] / 1e6:.2f} MB / "
                  f"{run['collective_bytes'] / 1e6:.2f} MB | {run['p2p_messages'] + run['collective_messages']} "
                  f"| {'-' if beta is None or run is not problem_runs[-1] else f'{beta:.0f}'} |")
        large = problem_runs[-1]
        log = os.path.join(out_dir, f"log_view_mumps-{problem}-{large['steps']}.txt")
        if beta is None or not os.path.exists(log):
            continue
        events = log_view(log)
        solve = events.get("SNESSolve", (0, 0.0))[1]
        analysis = events.get("MatLUFactorSym", (0, 0.0))[1]
        work, its = petsc_work(large)
        if solve <= 0 or its == 0:
            continue
        # Per iteration of the PETSc grids, per unknown of the largest.
        c = (beta * work / its / BANDWIDTH + mu * LATENCY) / (solve / its)
        model[problem] = (analysis / solve, c, solve, analysis)
    if not model:
        return
    print()
    print(f"Weak-scaling projection (network assumed {BANDWIDTH / 1e9:.0f} GB/s, {LATENCY * 1e6:.0f} µs "
          "a message; per Newton iteration, n unknowns a rank as at the largest N):")
    print()
    print("| problem | MUMPS analysis / 1-rank solve | communication / 1-rank solve | "
          + " | ".join(f"E({k})" for k in RANKS) + " |")
    print("|---|---|---|" + "---|" * len(RANKS))
    for problem, (seq, c, solve, analysis) in model.items():
        cells = []
        for k in RANKS:
            best = 1 / (k * seq + (1 - seq) + c)
            worst = 1 / (k * seq + (1 - seq) + k * c)
            cells.append(f"{worst:.2g}–{best:.2g}")
        print(f"| {problem} | {seq:.2f} ({analysis:.3g} of {solve:.3g} s) | {c:.3f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    OUT_DIR = sys.argv[1]
    machine = os.path.join(OUT_DIR, "machine.txt")
    if os.path.exists(machine):
        print(open(machine).read().strip())
        print()
    RUNS = load_runs(OUT_DIR)
    runs_table(RUNS)
    print()
    ratio_table(RUNS)
    print()
    goal(RUNS)
    print()
    log_view_table(OUT_DIR)
    print()
    projection(OUT_DIR)
