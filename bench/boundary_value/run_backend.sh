#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 34's benchmark of the PETSc back-end (README.md, "The PETSc
# back-end"): boundary_value_bench on each problem and N as dvi serial
# (--backend dvi), PETSc on 1 rank (--backend petsc) and PETSc on 2 ranks
# (mpiexec -n 2 … --backend petsc), one process per run, under
# /usr/bin/time -v for the peak RSS (for mpiexec: the largest rank's); the
# load average before every run; the answers of the three compared node by
# node (--dump) for N ≤ DUMP_MAX; PETSc's -log_view of the 1-rank solve at
# the largest N. Then backend_tables.py writes the table.
#   bench/boundary_value/run_backend.sh [OUT_DIR] [N ...]   # default N = 1e4 1e5 1e6
# writes OUT_DIR/backend.jsonl, OUT_DIR/log_view-PROBLEM-N.txt and
# OUT_DIR/backend_table.md (the table on stdout).
# BUILD_DIR (default /tmp/build-bvp-bench) selects the build tree; it is
# configured (Release, no tests) only when it has no CMakeCache.txt.
# TWO_RANKS_SKIP="game:1000000" skips those 2-rank runs (the game at 10⁶
# needs ~8 GB on one rank, more on two); REPEAT overrides the solves timed
# per run (default 3, 1 from 10⁶).
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-bvp-bench}
out_dir=${1:-$build_dir/boundary_value}
shift $(( $# > 0 ? 1 : 0 ))
sizes=("$@")
((${#sizes[@]})) || sizes=(10000 100000 1000000)
skip=" ${TWO_RANKS_SKIP:-} "
dump_max=${DUMP_MAX:-100000}
mkdir -p "$out_dir"
if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  "$src_dir/scripts/install-deps.sh"
  cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
    -DDVI_PETSC=ON >/dev/null
fi
cmake --build "$build_dir" --target boundary_value_bench -j2 >/dev/null
bench="$build_dir/bench/boundary_value_bench"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
results="$out_dir/backend.jsonl"
: > "$results"
echo "# $(bench_machine) at the start" > "$out_dir/machine.txt"

# run COLUMN PROBLEM N [extra bench args]: one line of backend.jsonl.
run() {
  local column=$1 problem=$2 n=$3
  shift 3
  local repeat=${REPEAT:-$(( n >= 1000000 ? 1 : 3 ))}
  local load args=(--problem "$problem" --steps "$n" --repeat "$repeat" "$@")
  local launch=()
  case $column in
    dvi) args+=(--backend dvi) ;;
    petsc1) args+=(--backend petsc) ;;
    petsc2) args+=(--backend petsc); launch=(mpiexec -n 2) ;;
  esac
  load=$(cut -d' ' -f1 /proc/loadavg)
  echo "load $load: $column $problem N = $n" >&2
  local line rss
  line=$(/usr/bin/time -v -o "$out_dir/time.txt" "${launch[@]}" "$bench" "${args[@]}" | tail -1) || true
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2 / 1024}' "$out_dir/time.txt")
  [[ $line == \{* ]] || line="{\"solver\": \"failed\", \"problem\": \"$problem\", \"steps\": $n"
  echo "${line%\}}, \"column\": \"$column\", \"load\": $load, \"time_rss_mb\": ${rss:-0}}" >> "$results"
}

for problem in lcs game; do
  for n in "${sizes[@]}"; do
    for column in dvi petsc1 petsc2; do
      [[ $column == petsc2 && $skip == *" $problem:$n "* ]] && continue
      if (( n <= dump_max )); then
        run "$column" "$problem" "$n" --dump "$out_dir/dump-$column-$problem-$n.bin"
      else
        run "$column" "$problem" "$n"
      fi
    done
  done
done
# Where PETSc's time goes at the largest N, on one rank.
n=${sizes[-1]}
for problem in lcs game; do
  echo "load $(cut -d' ' -f1 /proc/loadavg): -log_view $problem N = $n" >&2
  PETSC_OPTIONS="-log_view :$out_dir/log_view-$problem-$n.txt" \
    "$bench" --problem "$problem" --steps "$n" --backend petsc >/dev/null || true
done
/usr/bin/python3 "$src_dir/bench/boundary_value/backend_tables.py" "$out_dir" \
  | tee "$out_dir/backend_table.md"
