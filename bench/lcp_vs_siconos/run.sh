#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds lcp_vs_siconos in Release (with -j1: the machine is shared) and
# prints the side-by-side table of our LCP solvers and Siconos numerics.
#   bench/lcp_vs_siconos/run.sh [CSV_PATH] [lcp_vs_siconos options...]
# e.g. bench/lcp_vs_siconos/run.sh /tmp/lcp.csv --quick
# BUILD_DIR (default /tmp/build-bench) selects the build tree. Siconos'
# own diagnostics (stderr) go to $BUILD_DIR/lcp_vs_siconos.log.
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-bench}
csv=${1:-$build_dir/lcp_vs_siconos.csv}
shift $(( $# > 0 ? 1 : 0 ))
# The anchor: Siconos numerics from Debian.
bench_build "$build_dir" lcp_vs_siconos "Siconos numerics" libsiconos-numerics-dev
echo "# $(bench_machine)"
"$build_dir/bench/lcp_vs_siconos" --csv "$csv" "$@" 2>"$build_dir/lcp_vs_siconos.log"
echo "CSV: $csv"
