#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Set-up command 1: install what is missing, build, and run the main job:
# dvisim on the default scene, Siconos' diode bridge rectifier, writing its
# trajectory, summary and plot to out/diode-bridge.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build" -DDVI_BUILD_TESTS=OFF -DDVI_BUILD_BENCHMARKS=OFF
cd "$root"
build/src/dvisim/dvisim run examples/scenes/diode_bridge.json --out out/diode-bridge
echo "Plot:    $root/out/diode-bridge/plot.png (and plot.svg)"
echo "Summary: $root/out/diode-bridge/summary.json"
