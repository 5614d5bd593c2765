#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Set-up command 1: install what is missing, build, and run the main job:
# dvisim on the shipped example problem, printing its solution.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build" -DDVI_BUILD_TESTS=OFF -DDVI_BUILD_BENCHMARKS=OFF
"$root/build/src/dvisim/dvisim" solve "$root/examples/problems/lcp_p_matrix.json"
