#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds lcp_vs_siconos in Release (with -j1: the machine is shared) and
# prints the side-by-side table of our LCP solvers and Siconos numerics.
#   bench/lcp_vs_siconos/run.sh [CSV_PATH] [lcp_vs_siconos options...]
# e.g. bench/lcp_vs_siconos/run.sh /tmp/lcp.csv --quick
# BUILD_DIR (default /tmp/build-bench) selects the build tree. Siconos'
# own diagnostics (stderr) go to $BUILD_DIR/lcp_vs_siconos.log.
set -euo pipefail
# Siconos calls OpenBLAS (pthread build); one thread, as our solvers use.
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build_dir=${BUILD_DIR:-/tmp/build-bench}
csv=${1:-$build_dir/lcp_vs_siconos.csv}
shift $(( $# > 0 ? 1 : 0 ))
# The anchor: Siconos numerics from Debian, needed by this benchmark only.
"$src_dir/scripts/install-deps.sh" libsiconos-numerics-dev
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BUILD_TOOLS=OFF >/dev/null
cmake --build "$build_dir" --target lcp_vs_siconos -j1 >/dev/null
if [[ ! -x "$build_dir/bench/lcp_vs_siconos" ]]; then
  echo "lcp_vs_siconos was not built: Siconos numerics not found (see bench/lcp_vs_siconos/README.md)" >&2
  exit 1
fi
cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2 | xargs)
echo "# $(date -u +%F), $(nproc) cores ($cpu), Release build"
"$build_dir/bench/lcp_vs_siconos" --csv "$csv" "$@" 2>"$build_dir/lcp_vs_siconos.log"
echo "CSV: $csv"
