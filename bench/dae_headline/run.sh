#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds dae_headline in Release (with -j1: the machine is shared) and prints
# the diode-bridge headline (event-driven / auto against Siconos' kernel) and
# the "where methods fail" table of issue 5.
#   bench/dae_headline/run.sh [CSV_PATH]
# BUILD_DIR (default /tmp/build-daeheadline) selects the build tree. Progress
# and Siconos' own diagnostics (stderr) go to $BUILD_DIR/dae_headline.log.
set -euo pipefail
# Siconos calls OpenBLAS (pthread build); one thread, as our integrators use.
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build_dir=${BUILD_DIR:-/tmp/build-daeheadline}
csv=${1:-$build_dir/dae_headline.csv}
# The anchor: Siconos' kernel (and numerics) from Debian, for this benchmark only.
"$src_dir/scripts/install-deps.sh" libsiconos-kernel-dev libsiconos-numerics-dev
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BUILD_TOOLS=OFF >/dev/null
cmake --build "$build_dir" --target dae_headline -j1 >/dev/null
if [[ ! -x "$build_dir/bench/dae_headline" ]]; then
  echo "dae_headline was not built: Siconos kernel not found (see bench/dae_headline/README.md)" >&2
  exit 1
fi
cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2 | xargs)
echo "# $(date -u +%F), $(nproc) cores ($cpu), Release build, commit $(git -C "$src_dir" rev-parse --short HEAD 2>/dev/null || echo '?'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
"$build_dir/bench/dae_headline" --csv "$csv" 2>"$build_dir/dae_headline.log"
echo "CSV: $csv"
