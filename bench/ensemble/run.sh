#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Ensemble throughput (issue 34; README.md here): three sweeps of different
# member cost, each run by one process (no MPI), by `mpiexec -n 1` and by
# `mpiexec -n 2`; members per second, parallel efficiency, and a cost model
# of K ranks from the measured per-member costs (model.py, a gnuplot chart).
#   bench/ensemble/run.sh [OUT_DIR]
# BUILD_DIR (default /tmp/build-ensemble) selects the build tree.
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-ensemble}
out_dir=${1:-$build_dir/ensemble}
"$src_dir/scripts/install-deps.sh"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BUILD_BENCHMARKS=OFF -DDVI_MPI=ON "${launcher[@]}" >/dev/null
cmake --build "$build_dir" --target dvisim -j2 >/dev/null
dvisim=$build_dir/src/dvisim/dvisim
rm -rf "$out_dir"
mkdir -p "$out_dir"
scenes=$src_dir/examples/scenes

# name, member count, sweep body (scene + overrides).
write_sweep() {
  /usr/bin/python3 - "$out_dir/$1.json" "$scenes" "$2" <<'PY'
import json, sys
path, scenes, kind = sys.argv[1], sys.argv[2], sys.argv[3]
# Sizes: ~8–10 s of work each on one core, so that MPI's start-up (0.3–0.4 s
# measured) does not decide the comparison.
if kind == "cheap":      # the Filippov relay, event-driven: ~0.02 ms to integrate a member
    sweep = {"scene": scenes + "/filippov_relay.json", "members": [{"/method/name": "event"}],
             "grid": {"/problem/params/a": [0.005 * k for k in range(160)],
                      "/x0/0": [0.1 + 0.0125 * k for k in range(500)]}}
elif kind == "medium":   # the diode bridge at rtol 1e-8 over its start: ~8 ms
    sweep = {"scene": scenes + "/diode_bridge.json",
             "grid": {"/x0/0": [2 + 0.02 * k for k in range(500)], "/x0/1": [0.25 * j for j in range(6)]}}
else:                    # the diode bridge at rtol 1e-11: ~15 ms
    sweep = {"scene": scenes + "/diode_bridge.json", "members": [{"/method/rtol": 1e-11}],
             "grid": {"/x0/0": [2 + 0.05 * k for k in range(400)], "/x0/1": [0, 0.25, 0.5]}}
json.dump(sweep, open(path, "w"))
PY
}

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "# $(bench_machine)"
echo "# load before: $(uptime | sed 's/.*load average/load average/')"
results=$out_dir/results.csv
echo "sweep,launch,ranks,members,seconds" >"$results"
for sweep in cheap medium expensive; do
  write_sweep "$sweep" "$sweep"
  for launch in plain mpi1 mpi2; do
    case $launch in
      plain) command=("$dvisim"); ranks=1 ;;
      mpi1) command=(mpiexec -n 1 "$dvisim"); ranks=1 ;;
      mpi2) command=(mpiexec -n 2 "$dvisim"); ranks=2 ;;
    esac
    start=$(date +%s.%N)
    "${command[@]}" sweep "$out_dir/$sweep.json" --out "$out_dir/$sweep-$launch" >/dev/null
    end=$(date +%s.%N)
    members=$(($(wc -l <"$out_dir/$sweep-$launch/sweep.csv") - 1))
    echo "$sweep,$launch,$ranks,$members,$(echo "$end - $start" | bc -l)" >>"$results"
  done
done
echo "# load after: $(uptime | sed 's/.*load average/load average/')"
/usr/bin/python3 "$src_dir/bench/ensemble/model.py" "$out_dir"
