#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The boundary-value benchmark (README.md): dvi's aggregate VI against PETSc
# 3.18's SNESVI (vinewtonrsls, basic line search, KLU, one rank) on the
# identical assembled MCP, N = 10³ … 10⁶ steps, one process per (solver, N)
# so that each peak RSS is its own; then the table and the fitted exponents.
#   bench/boundary_value/run.sh [OUT_DIR] [N ...]
# e.g. bench/boundary_value/run.sh /tmp/bvp 1000 10000
# writes OUT_DIR/results.jsonl and OUT_DIR/table.md (the table on stdout).
# BUILD_DIR (default /tmp/build-bvp-bench) selects the build tree. PETSc is
# installed here (Debian petsc-dev), never by the default build.
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-bvp-bench}
out_dir=${1:-$build_dir/boundary_value}
shift $(( $# > 0 ? 1 : 0 ))
sizes=("$@")
((${#sizes[@]})) || sizes=(1000 10000 100000 1000000)
mkdir -p "$out_dir"
"$src_dir/scripts/install-deps.sh" petsc-dev
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BENCH_PETSC=ON >/dev/null
cmake --build "$build_dir" --target boundary_value_bench petsc_snesvi -j2 >/dev/null
header="# $(bench_machine) at the start"
# PETSc and OpenBLAS on one thread, as dvi's solve.
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
results="$out_dir/results.jsonl"
: > "$results"
for problem in lcs game; do
  for n in "${sizes[@]}"; do
    # Both solvers timed as the best of several solves in one process (a
    # run of a few milliseconds on a shared machine is mostly noise).
    repeat=$(( n <= 10000 ? 10 : 3 ))
    echo "load $(cut -d' ' -f1-3 /proc/loadavg): $problem N = $n" >&2
    "$build_dir/bench/boundary_value_bench" --problem "$problem" --steps "$n" --repeat "$repeat" \
      >> "$results" || true
    "$build_dir/bench/petsc_snesvi" --problem "$problem" --steps "$n" --repeat "$repeat" \
      >> "$results" || true
  done
done
# The table, and per solver the least-squares slope of log(time) on log(N),
# for the wall time and the CPU time.
awk -v header="$header" '
  function field(line, key,   pattern, value) {
    pattern = "\"" key "\": \"?[^,}\"]*"
    if (!match(line, pattern)) return ""
    value = substr(line, RSTART, RLENGTH)
    sub("\"" key "\": \"?", "", value)
    return value
  }
  function fit(p, s, clock, range,   key) {
    key = p SUBSEP s SUBSEP clock SUBSEP range
    if (k[key] < 2) return "-"
    return sprintf("%.3f", (k[key] * sxy[key] - sx[key] * sy[key]) / (k[key] * sxx[key] - sx[key] * sx[key]))
  }
  {
    p = field($0, "problem"); s = field($0, "solver"); n = field($0, "steps")
    key = p SUBSEP n
    if (!(key in seen)) { order[++count] = key; seen[key] = 1 }
    if (!(p in seen_problem)) { problems[++problem_count] = p; seen_problem[p] = 1 }
    wall[p, n, s] = field($0, "seconds"); cpu[p, n, s] = field($0, "cpu_seconds")
    its[p, n, s] = field($0, "iterations"); rss[p, n, s] = field($0, "peak_rss_mb")
    res[p, n, s] = field($0, "residual"); status[p, n, s] = field($0, "status")
    if (s == "dvi") total[p, n] = field($0, "total_iterations")
    unknowns[p, n] = field($0, "unknowns")
    if (status[p, n, s] == "success" || status[p, n, s] == "CONVERGED_FNORM_ABS") {
      x = log(n)
      # Two fits: over every N, and over N >= 10^4 (a solve of 10^3 steps
      # takes a millisecond, where fixed costs and timer noise weigh most).
      for (range = 1; range <= 2; ++range) {
        if (range == 2 && n < 10000) continue
        for (c = 1; c <= 2; ++c) {
          clock = c == 1 ? "wall" : "cpu"; y = log(c == 1 ? wall[p, n, s] : cpu[p, n, s])
          fk = p SUBSEP s SUBSEP clock SUBSEP range
          sx[fk] += x; sy[fk] += y; sxx[fk] += x * x; sxy[fk] += x * y; k[fk]++
        }
      }
    } else {
      failed[p, n, s] = 1
    }
  }
  END {
    print header
    print ""
    print "| problem | N | unknowns | dvi s (cpu) | PETSc s (cpu) | dvi/PETSc wall (cpu) | dvi Newton its, finest / all grids | PETSc its | dvi peak MB | PETSc peak MB | residual dvi / PETSc |"
    print "|---|---|---|---|---|---|---|---|---|---|---|"
    for (i = 1; i <= count; ++i) {
      split(order[i], parts, SUBSEP); p = parts[1]; n = parts[2]
      ratio = (wall[p, n, "petsc"] > 0) ? sprintf("%.2f (%.2f)", wall[p, n, "dvi"] / wall[p, n, "petsc"], cpu[p, n, "dvi"] / cpu[p, n, "petsc"]) : "-"
      printf "| %s | %d | %d | %.4g (%.4g)%s | %.4g (%.4g)%s | %s | %s / %s | %s | %.0f | %.0f | %s / %s |\n", p, n, unknowns[p, n], \
        wall[p, n, "dvi"], cpu[p, n, "dvi"], failed[p, n, "dvi"] ? " FAILED" : "", \
        wall[p, n, "petsc"], cpu[p, n, "petsc"], failed[p, n, "petsc"] ? " FAILED" : "", ratio, \
        its[p, n, "dvi"], total[p, n], its[p, n, "petsc"], rss[p, n, "dvi"], rss[p, n, "petsc"], \
        res[p, n, "dvi"], res[p, n, "petsc"]
    }
    print ""
    print "| problem | fitted exponent of time ~ N^e | dvi wall | dvi cpu | PETSc wall | PETSc cpu |"
    print "|---|---|---|---|---|---|"
    for (i = 1; i <= problem_count; ++i) {
      p = problems[i]
      for (range = 1; range <= 2; ++range)
        printf "| %s | over %d sizes%s | %s | %s | %s | %s |\n", p, \
          k[p SUBSEP "dvi" SUBSEP "wall" SUBSEP range], range == 2 ? " (N >= 10^4)" : "", \
          fit(p, "dvi", "wall", range), fit(p, "dvi", "cpu", range), \
          fit(p, "petsc", "wall", range), fit(p, "petsc", "cpu", range)
    }
  }' "$results" | tee "$out_dir/table.md"
