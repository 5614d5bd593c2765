# SPDX-License-Identifier: Apache-2.0
import pathlib
import sys

# The examples are imported by the tests as modules.
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "examples"))
