#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and runs
# each for SECONDS (default 60) on a scratch copy of its corpus, two at a
# time; fails on the first crash, hang, leak or sanitizer report, leaving
# the input that caused it in build-fuzz/findings/TARGET/. See README.md.
# Usage: run.sh [SECONDS] [TARGET ...]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scene_fuzzer problem_fuzzer complementarity_fuzzer run_fuzzer)

build="$root/build-fuzz"
# A fresh tree builds the targets alone; one already configured keeps its
# settings (.ci/run's has the test suite in it too: one sanitizer build).
[[ -f $build/CMakeCache.txt ]] ||
  "$root/scripts/configure-sanitized.sh" "$build" -DDVI_BUILD_TESTS=OFF
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"

corpus="$root/tests/fuzz/corpus"
# The corpora each target starts from: its own seeds, and examples/.
seeds() {
  case "$1" in
    scene_fuzzer) echo "$corpus/scene $root/examples/scenes" ;;
    problem_fuzzer) echo "$corpus/problem $root/examples/problems" ;;
    complementarity_fuzzer) echo "$corpus/complementarity" ;;
    run_fuzzer) echo "$corpus/run $corpus/scene $root/examples/scenes" ;;
  esac
}

# One target: its scratch corpus first (libFuzzer adds to the first
# directory), the committed seeds read-only after it.
fuzz() {
  local target=$1 work="$build/corpus/$1" findings="$build/findings/$1"
  rm -rf "$work" "$findings"
  mkdir -p "$work" "$findings"
  local dict=()
  [[ $target == scene_fuzzer || $target == problem_fuzzer || $target == run_fuzzer ]] &&
    dict=(-dict="$root/tests/fuzz/scene.dict")
  # shellcheck disable=SC2046
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/tests/fuzz/$target" "$work" $(seeds "$target") "${dict[@]}" \
      -max_total_time="$seconds" -timeout=25 -rss_limit_mb=4096 -max_len=8192 \
      -artifact_prefix="$findings/" -print_final_stats=1 >"$build/$target.log" 2>&1
}

status=0
pids=()
for target in "${targets[@]}"; do
  fuzz "$target" &
  pids+=($!)
  if ((${#pids[@]} == 2)); then
    wait "${pids[0]}" || status=1
    pids=("${pids[1]}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done

for target in "${targets[@]}"; do
  echo "== $target: $(grep -E '^stat::number_of_executed_units' "$build/$target.log" | awk '{print $2}') runs," \
       "$(grep -oE 'cov: [0-9]+' "$build/$target.log" | tail -1) edges"
  if ls "$build/findings/$target"/* >/dev/null 2>&1; then
    echo "   FINDING: $(ls "$build/findings/$target")"; tail -30 "$build/$target.log"; status=1
  fi
done
exit "$status"
