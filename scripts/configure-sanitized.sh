#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Configures BUILD_DIR for the sanitizer builds: clang 14, AddressSanitizer +
# UndefinedBehaviorSanitizer, and libFuzzer's coverage in all our code
# (DVI_FUZZ), at -O1 with line tables (fast to build, stacks readable;
# asserts, Eigen's, stay on). One such tree serves both the test suite under
# the sanitizers and the fuzz targets (.ci/run), so CI compiles the library
# under the sanitizers once. Extra arguments go to cmake.
# Usage: configure-sanitized.sh BUILD_DIR [cmake args ...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: configure-sanitized.sh BUILD_DIR [cmake args ...]}
shift
# Debian's clang 14; libFuzzer's runtime (libclang_rt.fuzzer-x86_64.a) is in
# libclang-rt-14-dev.
"$root/scripts/install-deps.sh" clang libclang-rt-14-dev
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
      -DDVI_FUZZ=ON -DDVI_BUILD_BENCHMARKS=OFF "$@" >/dev/null
