# SPDX-License-Identifier: Apache-2.0
"""Every C++ example of the README has a Python twin whose numbers match."""
import os
import re
import subprocess

import pytest

import diode_bridge_rectifier
import quick_start

# The same library runs the same problem with the same options: only the
# decimal printing of the C++ side (17 significant digits) separates them.
TWIN_AGREEMENT = 1e-12


def cxx_output(variable):
    """The output of the example program the test's environment names."""
    program = os.environ.get(variable)
    if not program:
        pytest.skip("examples are not built (DVI_BUILD_EXAMPLES=OFF)")
    return subprocess.run([program], check=True, capture_output=True, text=True).stdout


def cxx_clamp_time():
    out = cxx_output("DVI_QUICK_START")
    return float(re.search(r"diode clamps at t = (\S+)", out).group(1))


def test_quick_start_twin_matches_cxx():
    status, clamp = quick_start.main()
    assert status == 0
    assert abs(clamp - cxx_clamp_time()) <= TWIN_AGREEMENT


def test_diode_bridge_rectifier_twin_matches_cxx():
    """README's longer program: θ time-stepping's errors against the exact
    RLC solution, per scheme and h. The same steps; the exact solution is
    evaluated by each language's own cos/exp (a few ulps of 10 V apart)."""
    status, rows = diode_bridge_rectifier.main()
    assert status == 0
    cxx = [float(error) for error in
           re.findall(r"^\s+\S+\s+(\S+)\s+\S+$", cxx_output("DVI_DIODE_BRIDGE_RECTIFIER"),
                      re.MULTILINE)]
    assert len(cxx) == len(rows) == 8
    for (scheme, h, error), cxx_error in zip(rows, cxx):
        assert abs(error - cxx_error) <= TWIN_AGREEMENT, (scheme, h)
