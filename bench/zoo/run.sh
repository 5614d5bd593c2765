#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The circuit and controller zoo benchmark (README.md here): builds dvisim,
# zoo_siconos and zoo_bench in Release (-j2: the machine is shared), runs
# Siconos on every model, then every scene through dvisim's auto, event and
# stepping, and prints the tables and the issue's goals.
#   bench/zoo/run.sh [OUT_DIR] [zoo_bench options, e.g. --model rlc_diode]
# BUILD_DIR (default /tmp/build-zoo) selects the build tree; OUT_DIR
# (default $BUILD_DIR/zoo) receives zoo.csv, siconos.csv, every run's
# outputs under runs/ and dvisim's plot of each model under pictures/.
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-zoo}
out_dir=${1:-$build_dir/zoo}
shift $(( $# > 0 ? 1 : 0 ))
# The anchor: Siconos' kernel (and numerics) from Debian, for benchmarks only.
"$src_dir/scripts/install-deps.sh" libsiconos-kernel-dev libsiconos-numerics-dev
# ccache, where installed, makes the rebuild after a change a matter of seconds.
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  "${launcher[@]}" >/dev/null
cmake --build "$build_dir" --target dvisim zoo_bench zoo_siconos -j2 >/dev/null
mkdir -p "$out_dir"
echo "# $(bench_machine)"
echo "# load before: $(uptime | sed 's/.*load average/load average/')"
start=$(date +%s)
# Siconos' own diagnostics (stderr) go to siconos.log.
"$build_dir/bench/zoo/zoo_siconos" --csv "$out_dir/siconos.csv" 2>"$out_dir/siconos.log"
"$build_dir/bench/zoo/zoo_bench" --dvisim "$build_dir/src/dvisim/dvisim" \
  --scenes "$src_dir/examples/scenes/zoo" --siconos "$out_dir/siconos.csv" --out "$out_dir" "$@" \
  2>"$out_dir/zoo_bench.log"
echo
echo "# $(( $(date +%s) - start )) s; load after: $(uptime | sed 's/.*load average/load average/')"
echo "# CSV: $out_dir/zoo.csv, $out_dir/siconos.csv; pictures: $out_dir/pictures/"
