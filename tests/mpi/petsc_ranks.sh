#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 34's scene-level test of the PETSc back-end: the LQ Nash game and
# the periodic rectifier (examples/scenes) run by `dvisim run` with
# method.backend "dvi" (serial Newton), "petsc" on one process and "petsc"
# under `mpiexec -n 2`. Every sample of trajectory.csv agrees within
# 2·steps·tol (each solve stops at a natural residual ≤ tol = 1e-10, and a
# residual ε in the x-rows moves x by at most ε a step), summary.json's
# residual is ≤ tol, and the 2-rank run prints its summary once and writes
# the same files as the serial one (rank 0 alone writes).
# Usage: petsc_ranks.sh DVISIM MPIEXEC SOURCE_DIR
set -euo pipefail
dvisim=$1 mpiexec=$2 source_dir=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

for scene in nash_game periodic_rectifier; do
  for backend in dvi petsc; do
    /usr/bin/python3 - "$source_dir/examples/scenes/$scene.json" "$work/$scene-$backend.json" \
      "$backend" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["method"]["backend"] = sys.argv[3]
scene["output"]["plot"] = False
json.dump(scene, open(sys.argv[2], "w"))
PY
  done
  "$dvisim" run "$work/$scene-dvi.json" --out "$work/$scene-serial" >/dev/null
  "$dvisim" run "$work/$scene-petsc.json" --out "$work/$scene-one" >/dev/null
  "$mpiexec" -n 2 "$dvisim" run "$work/$scene-petsc.json" --out "$work/$scene-two" \
    >"$work/$scene-two.log"
  summaries=$(grep -c "trajectory.csv" "$work/$scene-two.log" || true)
  [[ $summaries -eq 1 ]] || {
    echo "FAIL: $scene on 2 ranks printed $summaries summaries, expected 1:"
    cat "$work/$scene-two.log"; exit 1; }
  cmp <(ls "$work/$scene-serial") <(ls "$work/$scene-two") || {
    echo "FAIL: $scene on 2 ranks wrote other files than the serial run"; exit 1; }
  /usr/bin/python3 - "$work" "$scene" <<'PY'
import csv, json, sys
work, scene = sys.argv[1], sys.argv[2]
def rows(run):
    with open(f"{work}/{scene}-{run}/trajectory.csv") as f:
        return [r for r in csv.reader(f) if r and not r[0].startswith("#")]
serial = rows("serial")
summary = json.load(open(f"{work}/{scene}-serial/summary.json"))
steps = summary["steps"]
tolerance = 1e-10
bound = 2 * steps * tolerance
for run in ("one", "two"):
    other = rows(run)
    assert other[0] == serial[0], f"{run}: header {other[0]} != {serial[0]}"
    assert len(other) == len(serial), f"{run}: {len(other)} rows, serial {len(serial)}"
    worst = max(abs(float(a) - float(b)) for ra, rb in zip(serial[1:], other[1:])
                for a, b in zip(ra, rb))
    newton = json.load(open(f"{work}/{scene}-{run}/summary.json"))["newton"]
    residual = newton["residual"]
    ranks = {"one": "on 1 rank", "two": "on 2 ranks"}[run]
    assert f"PETSc SNES vinewtonrsls {ranks}" in newton["message"], newton["message"]
    print(f"{scene} petsc {run}: max |difference| = {worst:.3g} (bound {bound:.3g}), "
          f"residual {residual:.3g}")
    if worst > bound or residual > tolerance:
        sys.exit(1)
PY
done
echo "PASS: nash game and periodic rectifier, petsc on 1 and 2 ranks = serial dvi"
