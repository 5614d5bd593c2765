#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds stepping_vs_siconos in Release (with -j1: the machine is shared) and
# prints the side-by-side tables of our LCS time-stepping and Siconos' kernel.
#   bench/stepping_vs_siconos/run.sh [CSV_PATH] [stepping_vs_siconos options...]
# e.g. bench/stepping_vs_siconos/run.sh /tmp/stepping.csv --quick
# BUILD_DIR (default /tmp/build-benchstep) selects the build tree. Siconos'
# own diagnostics (stderr) go to $BUILD_DIR/stepping_vs_siconos.log.
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-benchstep}
csv=${1:-$build_dir/stepping_vs_siconos.csv}
shift $(( $# > 0 ? 1 : 0 ))
# The anchor: Siconos' kernel (and numerics) from Debian.
bench_build "$build_dir" stepping_vs_siconos "Siconos kernel" libsiconos-kernel-dev \
  libsiconos-numerics-dev
echo "# $(bench_machine)"
"$build_dir/bench/stepping_vs_siconos" --csv "$csv" "$@" 2>"$build_dir/stepping_vs_siconos.log"
echo "CSV: $csv"
