#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds stepping_vs_siconos in Release (with -j1: the machine is shared) and
# prints the side-by-side tables of our LCS time-stepping and Siconos' kernel.
#   bench/stepping_vs_siconos/run.sh [CSV_PATH] [stepping_vs_siconos options...]
# e.g. bench/stepping_vs_siconos/run.sh /tmp/stepping.csv --quick
# BUILD_DIR (default /tmp/build-benchstep) selects the build tree. Siconos'
# own diagnostics (stderr) go to $BUILD_DIR/stepping_vs_siconos.log.
set -euo pipefail
# Siconos calls OpenBLAS (pthread build); one thread, as our integrator uses.
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build_dir=${BUILD_DIR:-/tmp/build-benchstep}
csv=${1:-$build_dir/stepping_vs_siconos.csv}
shift $(( $# > 0 ? 1 : 0 ))
# The anchor: Siconos' kernel (and numerics) from Debian, for this benchmark only.
"$src_dir/scripts/install-deps.sh" libsiconos-kernel-dev libsiconos-numerics-dev
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BUILD_TOOLS=OFF >/dev/null
cmake --build "$build_dir" --target stepping_vs_siconos -j1 >/dev/null
if [[ ! -x "$build_dir/bench/stepping_vs_siconos" ]]; then
  echo "stepping_vs_siconos was not built: Siconos kernel not found (see bench/stepping_vs_siconos/README.md)" >&2
  exit 1
fi
cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2 | xargs)
echo "# $(date -u +%F), $(nproc) cores ($cpu), Release build, commit $(git -C "$src_dir" rev-parse --short HEAD 2>/dev/null || echo '?')"
"$build_dir/bench/stepping_vs_siconos" --csv "$csv" "$@" 2>"$build_dir/stepping_vs_siconos.log"
echo "CSV: $csv"
