#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Set-up command 2: install what is missing, build, and run the test suite.
# Tests and dvisim are switched on whatever build/ was configured with
# before (the main job configures it without tests), and a run of no test
# fails: "No tests were found" is not a pass.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build" -DDVI_BUILD_TESTS=ON -DDVI_BUILD_TOOLS=ON
cd "$root/build"
ctest --output-on-failure --no-tests=error -j"$(nproc)" --timeout 600
