#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds work_precision_dae in Release (with -j1: the machine is shared), runs
# it and draws issue 5's work-precision chart (max error against wall time,
# one panel per problem) with gnuplot.
#   bench/work_precision_dae/run.sh OUT_DIR [work_precision_dae options...]
# options: --budget SECONDS (default 10), --problem NAME (repeatable; wall,
# sliding, filippov2d, bridge; default all), e.g.
#   bench/work_precision_dae/run.sh /tmp/wpdae --budget 2 --problem wall
# writes OUT_DIR/work_precision_dae.{csv,md,png,svg} and goals.csv (the
# tables on stdout too). BUILD_DIR (default /tmp/build-wpdae) selects the
# build tree; progress and Siconos' own diagnostics (stderr) go to
# OUT_DIR/work_precision_dae.log.
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT_DIR [work_precision_dae options...]" >&2
  exit 2
fi
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-wpdae}
out_dir=$1
shift
mkdir -p "$out_dir"
# The anchor: Siconos' kernel (and numerics) from Debian.
bench_build "$build_dir" work_precision_dae "Siconos kernel" libsiconos-kernel-dev \
  libsiconos-numerics-dev
csv="$out_dir/work_precision_dae.csv"
goals="$out_dir/goals.csv"
{
  echo "# $(bench_machine) at start"
  "$build_dir/bench/work_precision_dae" --csv "$csv" --goals "$goals" "$@" \
    2>"$out_dir/work_precision_dae.log"
  echo "load average at end $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$out_dir/work_precision_dae.md"

# One data file per (problem, method): wall seconds, max error on the grid,
# max error on the grid and the exact solution's switch times.
data_dir="$out_dir/data"
rm -rf "$data_dir"
mkdir -p "$data_dir"
awk -F, -v dir="$data_dir" \
  'NR > 1 && $10 == "ok" { print $7, $5, $6 > (dir "/" $1 "_" $2 ".dat") }' "$csv"

methods="auto event stepping-theta0 stepping-theta0.5 siconos-theta0 siconos-theta0.5"
# Same colour for the same scheme; Siconos dashed.
declare -A style=(
  [auto]="lc rgb 'black' lw 2 pt 7" [event]="lc rgb 'dark-green' pt 5"
  [stepping-theta0]="lc rgb 'blue' pt 1" [stepping-theta0.5]="lc rgb 'red' pt 2"
  [siconos-theta0]="lc rgb 'blue' dt 2 pt 6" [siconos-theta0.5]="lc rgb 'red' dt 2 pt 8")
# The problems run (--problem may select some), in the table's order.
problems=$(awk -F, 'NR > 1 && !seen[$1]++ { print $1 }' "$csv")
panels=$(wc -w <<<"$problems")
plot_panels() {  # $1: column of the error (2 grid, 3 grid + switches), $2: its name in goals.csv
  for problem in $problems; do
    # The goal's error level: the smallest error of time-stepping in the budget
    # (dashed in both rows; the top row's is the goal's).
    local target
    target=$(awk -F, -v p="$problem" -v g="$2" '$1 == p && $2 == g { print $4 }' "$goals")
    echo "unset arrow"
    if [[ -n "$target" ]]; then
      echo "set arrow from graph 0, first $target to graph 1, first $target nohead dt 2 lc rgb 'gray'"
    fi
    echo "set title '$problem ($2)'; set xlabel 'wall time [s]'; set ylabel 'max error'"
    local plot="plot"
    for method in $methods; do
      local file="$data_dir/${problem}_${method}.dat"
      [[ -s "$file" ]] && plot="$plot '$file' using 1:$1 with linespoints ${style[$method]} title '$method',"
    done
    # No successful run: an empty panel keeps the layout.
    [[ $plot == plot ]] && plot="set multiplot next"
    echo "${plot%,}"
  done
}
for extension in png svg; do
  size="$((panels < 2 ? 1000 : 500 * panels)),1000"
  terminal="svg size $size"
  [[ $extension == png ]] && terminal="pngcairo size $size"
  {
    echo "set terminal $terminal font ',10'"
    echo "set output '$out_dir/work_precision_dae.$extension'"
    echo "set logscale xy; set format x '10^{%T}'; set format y '10^{%T}'"
    echo "set grid; set key top right font ',8'"
    echo "set multiplot layout 2,$panels title 'Issue 5 work-precision: max error vs wall time," \
         "over [0, T] (the 1001-point grid and the switch times, top: the goal) and on the grid" \
         "alone (bottom); dashed: the smallest stepping error'"
    plot_panels 3 "grid + switches"
    plot_panels 2 grid
    echo "unset multiplot"
  } | gnuplot
done
echo "chart: $out_dir/work_precision_dae.png, $out_dir/work_precision_dae.svg"
