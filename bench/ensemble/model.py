#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Throughput table and cost model of the ensemble benchmark (run.sh).

Measured: members per second of each sweep by one process, by mpiexec -n 1
and -n 2, and the parallel efficiency (throughput on 2 ranks over twice that
of mpiexec -n 1). Model: a sweep on K ranks takes
    T(K) = launch + max_r sum_{i = r mod K} (c_i + o) + gather,
with c_i each member's own integration time (sweep.csv's wall_seconds, from
the one-process run), o the rest of a member's cost in that run (reading its
scene, compiling its expressions: (T_plain - sum c_i) / members), `launch`
what `mpiexec -n 1` adds to the plain run (MPI's start-up), and the gather,
~(130 + 8 n) bytes per member at 1 GB/s. What 2 cores cannot show — K > 2 —
is the model's, drawn in throughput.png.
"""
import csv
import subprocess
import sys

out = sys.argv[1]
runs = {}
for row in csv.DictReader(open(f"{out}/results.csv")):
    runs[(row["sweep"], row["launch"])] = (int(row["members"]), float(row["seconds"]))

print("\n| sweep | members | member cost median [ms] | 1 process [members/s] | mpiexec -n 1 | mpiexec -n 2 | 2 ranks / 1 | efficiency |")
print("|---|---|---|---|---|---|---|---|")
model_rows = []
for sweep in ("cheap", "medium", "expensive"):
    costs = [float(r["wall_seconds"]) for r in csv.DictReader(open(f"{out}/{sweep}-plain/sweep.csv"))]
    states = sum(1 for c in next(csv.reader(open(f"{out}/{sweep}-plain/sweep.csv"))) if c.startswith("x"))
    n, plain = runs[(sweep, "plain")]
    _, one = runs[(sweep, "mpi1")]
    _, two = runs[(sweep, "mpi2")]
    median = sorted(costs)[len(costs) // 2]
    speedup = one / two
    print(f"| {sweep} | {n} | {median * 1e3:.3g} | {n / plain:.4g} | {n / one:.4g} | {n / two:.4g} | "
          f"{speedup:.2f}× | {speedup / 2:.0%} |")
    launch = max(0.0, one - plain)
    per_member = max(0.0, (plain - sum(costs)) / n)
    predicted = []
    for k in (1, 2, 4, 8, 16, 32, 64, 128):
        makespan = max(sum(costs[r::k]) + per_member * len(costs[r::k]) for r in range(k))
        gather = n * (130 + 8 * states) / 1e9
        predicted.append((k, n / (launch + makespan + gather)))
    model_rows.append((sweep, launch, predicted))

print("\nModel (members/s on K ranks; launch = measured overhead of one mpiexec run):\n")
print("| sweep | launch [s] | " + " | ".join(f"K = {k}" for k, _ in model_rows[0][2]) + " |")
print("|---|---|" + "---|" * len(model_rows[0][2]))
for sweep, launch, predicted in model_rows:
    print(f"| {sweep} | {launch:.3f} | " + " | ".join(f"{p:.4g}" for _, p in predicted) + " |")

with open(f"{out}/model.dat", "w") as data:
    for sweep, _, predicted in model_rows:
        data.write(f"# {sweep}\n")
        for k, p in predicted:
            data.write(f"{k} {p}\n")
        data.write("\n\n")
script = f"""set terminal pngcairo size 800,500
set output '{out}/throughput.png'
set logscale xy
set xlabel 'ranks K'
set ylabel 'members per second (model)'
set key left top
plot for [i=0:2] '{out}/model.dat' index i using 1:2 with linespoints title columnheader(1)
"""
script = script.replace("title columnheader(1)", "title word('cheap medium expensive', i+1)")
subprocess.run(["gnuplot"], input=script, text=True, check=True)
print(f"\nchart: {out}/throughput.png")
