# SPDX-License-Identifier: Apache-2.0
"""Every C++ example of the README has a Python twin whose numbers match."""
import os
import re
import subprocess

import pytest

import quick_start

# The same library runs the same problem with the same options: only the
# decimal printing of the C++ side (17 significant digits) separates them.
TWIN_AGREEMENT = 1e-12


def cxx_clamp_time():
    program = os.environ.get("DVI_QUICK_START")
    if not program:
        pytest.skip("examples are not built (DVI_BUILD_EXAMPLES=OFF)")
    out = subprocess.run([program], check=True, capture_output=True, text=True).stdout
    return float(re.search(r"diode clamps at t = (\S+)", out).group(1))


def test_quick_start_twin_matches_cxx():
    status, clamp = quick_start.main()
    assert status == 0
    assert abs(clamp - cxx_clamp_time()) <= TWIN_AGREEMENT
