#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds dae_headline in Release (with -j1: the machine is shared) and prints
# the diode-bridge headline (event-driven / auto against Siconos' kernel) and
# the "where methods fail" table of issue 5.
#   bench/dae_headline/run.sh [CSV_PATH [ARGS...]]
# ARGS go to dae_headline: --protocol issue31, --rtols 1e-7,5e-8 (issue 31's
# own-grid table with the physical-limit oracle, at the rtols given).
# BUILD_DIR (default /tmp/build-daeheadline) selects the build tree. Progress
# and Siconos' own diagnostics (stderr) go to $BUILD_DIR/dae_headline.log.
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-daeheadline}
csv=${1:-$build_dir/dae_headline.csv}
shift || true
# The anchor: Siconos' kernel (and numerics) from Debian.
bench_build "$build_dir" dae_headline "Siconos kernel" libsiconos-kernel-dev libsiconos-numerics-dev
echo "# $(bench_machine)"
"$build_dir/bench/dae_headline" --csv "$csv" "$@" 2>"$build_dir/dae_headline.log"
echo "CSV: $csv"
