#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds work_precision in Release (with -j1: the machine is shared), runs it
# and draws the work-precision chart with gnuplot.
#   bench/work_precision.sh OUT_DIR [work_precision options...]
# e.g. bench/work_precision.sh /tmp/wp --budget 2
# writes OUT_DIR/work_precision.{csv,png,svg,md} (the table on stdout too).
# BUILD_DIR (default /tmp/build-wp) selects the build tree.
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT_DIR [work_precision options...]" >&2
  exit 2
fi
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-/tmp/build-wp}
out_dir=$1
shift
mkdir -p "$out_dir"
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BUILD_TOOLS=OFF >/dev/null
cmake --build "$build_dir" --target work_precision -j1 >/dev/null
if [[ ! -x "$build_dir/bench/work_precision" ]]; then
  echo "work_precision was not built: Boost headers not found (see bench/README.md)" >&2
  exit 1
fi
cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2 | xargs)
csv="$out_dir/work_precision.csv"
{
  echo "# $(date -u +%F), $(nproc) cores ($cpu), Release build, commit $(git -C "$src_dir" rev-parse --short HEAD 2>/dev/null || echo '?')"
  "$build_dir/bench/work_precision" --csv "$csv" "$@"
} | tee "$out_dir/work_precision.md"

# One data file per (problem, method): max error, seconds, RHS evaluations.
data_dir="$out_dir/data"
rm -rf "$data_dir"
mkdir -p "$data_dir"
awk -F, -v dir="$data_dir" \
  'NR > 1 && $9 == "ok" { print $5, $6, $7 > (dir "/" $1 "_" $2 ".dat") }' "$csv"

methods="event oracle cvode dopri5 rosenbrock4 stepping-theta0 stepping-theta0.5"
problems=$(awk -F, 'NR > 1 && !seen[$1]++ { printf "%s ", $1 }' "$csv")
columns=$(wc -w <<<"$problems")
plot_panels() {  # $1: column of the cost (2 seconds, 3 RHS evaluations), $2: its label
  for problem in $problems; do
    echo "set title '$problem'; set xlabel 'max error'; set ylabel '$2'"
    local plot="plot"
    for method in $methods; do
      local file="$data_dir/${problem}_${method}.dat"
      [[ -s "$file" ]] && plot="$plot '$file' using 1:$1 with linespoints title '$method',"
    done
    echo "${plot%,}"
  done
}
for extension in png svg; do
  terminal="svg size $((600 * columns)),1000"
  [[ $extension == png ]] && terminal="pngcairo size $((600 * columns)),1000"
  {
    echo "set terminal $terminal font ',10'"
    echo "set output '$out_dir/work_precision.$extension'"
    echo "set logscale xy; set format x '10^{%T}'; set format y '10^{%T}'"
    echo "set grid; set key top right font ',8'"
    echo "set multiplot layout 2,$columns title 'Work-precision: error vs wall time (top)" \
         "and RHS evaluations (bottom)'"
    plot_panels 2 "wall time [s]"
    plot_panels 3 "RHS evaluations"
    echo "unset multiplot"
  } | gnuplot
done
echo "chart: $out_dir/work_precision.png, $out_dir/work_precision.svg"
