#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Shell functions the benchmarks' run.sh share. Each sets src_dir (the
# repository's root) and sources this file:
#   source "$src_dir/bench/common/run_common.sh"

# Siconos calls OpenBLAS (pthread build); one thread, as our solvers and
# integrators use.
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}

# bench_build BUILD_DIR TARGET ANCHOR PACKAGE...: installs the anchor's
# Debian PACKAGEs (for this benchmark only), builds TARGET in Release in
# BUILD_DIR (-j1: the machine is shared; no tests, no tools) and exits 1
# when it was not built because ANCHOR (e.g. "Siconos kernel") was not found.
bench_build() {
  local build_dir=$1 target=$2 anchor=$3
  shift 3
  "$src_dir/scripts/install-deps.sh" "$@"
  cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DDVI_BUILD_TESTS=OFF \
    -DDVI_BUILD_TOOLS=OFF >/dev/null
  cmake --build "$build_dir" --target "$target" -j1 >/dev/null
  if [[ ! -x "$build_dir/bench/$target" ]]; then
    echo "$target was not built: $anchor not found (see bench/$target/README.md)" >&2
    exit 1
  fi
}

# bench_machine: the line a result starts with: date, cores, CPU, build,
# commit and the load average now.
bench_machine() {
  local cpu commit
  cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2 | xargs)
  commit=$(git -C "$src_dir" rev-parse --short HEAD 2>/dev/null || echo '?')
  echo "$(date -u +%F), $(nproc) cores ($cpu), Release build, commit $commit, load average $(cut -d' ' -f1-3 /proc/loadavg)"
}
