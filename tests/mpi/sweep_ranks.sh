#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 34's rank-count test: a sweep of 240 members (the Filippov relay over
# its drift a, start x0 and two methods) run by one process and by
# `mpiexec -n 2` gives the same sweep.csv and the same per-member files, bit
# for bit, apart from the wall-clock times; every member succeeds and the
# event-driven members end at the exact x(T) = max(0, x0 − (1 − a)T).
# Usage: sweep_ranks.sh DVISIM MPIEXEC SOURCE_DIR
set -euo pipefail
dvisim=$1 mpiexec=$2 source_dir=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$source_dir" "$work/sweep.json" <<'PY'
import json, sys
source_dir, path = sys.argv[1], sys.argv[2]
json.dump({
    "scene": source_dir + "/examples/scenes/filippov_relay.json",
    "members": [{"/method/name": "event"}, {"/method/name": "stepping", "/method/h": 0.01}],
    "grid": {"/problem/params/a": [0.05 * k for k in range(12)],
             "/x0/0": [0.5 + 0.25 * k for k in range(10)]},
}, open(path, "w"))
PY

"$dvisim" sweep "$work/sweep.json" --out "$work/one" --trajectories >/dev/null
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
  "$mpiexec" -n 2 "$dvisim" sweep "$work/sweep.json" --out "$work/two" --trajectories \
  >"$work/two.log"
grep -q "240 members on 2 rank(s), 240 succeeded" "$work/two.log" || {
  echo "FAIL: expected 240 members on 2 ranks, all succeeded:"; cat "$work/two.log"; exit 1; }

# Every column but the last (wall_seconds).
strip_wall() { sed 's/,[^,]*$//' "$1"; }
cmp <(strip_wall "$work/one/sweep.csv") <(strip_wall "$work/two/sweep.csv") || {
  echo "FAIL: sweep.csv differs between 1 process and 2 ranks"; exit 1; }
rows=$(($(wc -l <"$work/one/sweep.csv") - 1))
[[ $rows -eq 240 ]] || { echo "FAIL: $rows rows, expected 240"; exit 1; }
for k in $(seq 0 239); do
  cmp "$work/one/members/$k/trajectory.csv" "$work/two/members/$k/trajectory.csv" || {
    echo "FAIL: member $k's trajectory.csv differs"; exit 1; }
  cmp <(grep -v wall_seconds "$work/one/members/$k/summary.json") \
      <(grep -v wall_seconds "$work/two/members/$k/summary.json") || {
    echo "FAIL: member $k's summary.json differs"; exit 1; }
done

# The event-driven members (0 … 119) against the exact final state, T = 4.
python3 - "$work/one/sweep.csv" <<'PY'
import csv, sys
worst = 0.0
for row in csv.DictReader(open(sys.argv[1])):
    if row["/method/name"] != "event":
        continue
    a, x0 = float(row["/problem/params/a"]), float(row["/x0/0"])
    exact = max(0.0, x0 - (1 - a) * 4)
    worst = max(worst, abs(float(row["x1"]) - exact))
print(f"event members: max |x(T) - exact| = {worst:.3g}")
sys.exit(0 if worst <= 1e-8 else 1)
PY
echo "PASS: 240 members, 1 process and 2 ranks identical"
