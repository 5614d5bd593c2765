#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Configures and builds dvi in build/ (Release). Extra arguments go to cmake.
# Usage: build.sh [BUILD_DIR] [cmake args ...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
shift || true
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build" -j"$(nproc)"
