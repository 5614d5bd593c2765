#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Set-up command 2: install what is missing, build, and run the test suite.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build"
cd "$root/build"
ctest --output-on-failure -j"$(nproc)" --timeout 600
