#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds work_precision in Release (with -j1: the machine is shared) and runs
# it: a `dvisim study` of each scene in bench/work_precision/scenes plus the oracle and the
# goals of the issue.
#   bench/work_precision/run.sh OUT_DIR [work_precision options...]
# e.g. bench/work_precision/run.sh /tmp/wp --problem clamp
# writes OUT_DIR/work_precision.{csv,md} (the table on stdout too) and each
# problem's study (index.html, study.csv, work_precision.png, ...) in
# OUT_DIR/NAME/. BUILD_DIR (default /tmp/build-wp) selects the build tree.
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT_DIR [work_precision options...]" >&2
  exit 2
fi
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$src_dir/bench/common/run_common.sh"
build_dir=${BUILD_DIR:-/tmp/build-wp}
out_dir=$1
shift
mkdir -p "$out_dir"
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
  -DDVI_BUILD_TOOLS=ON >/dev/null
cmake --build "$build_dir" --target work_precision -j1 >/dev/null
{
  echo "# $(bench_machine)"
  "$build_dir/bench/work_precision" --out "$out_dir" "$@"
} | tee "$out_dir/work_precision.md"
echo "pages: $out_dir/*/index.html"
