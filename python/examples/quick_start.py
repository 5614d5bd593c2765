# SPDX-License-Identifier: Apache-2.0
"""README's example from Python: a capacitor drained by a current source into
an ideal diode, v' = -v - 1 + u, 0 <= u ⊥ v >= 0. From v(0) = 1 the diode
clamps v at 0 at t = ln 2. The twin of examples/quick_start.cpp."""
import math

import numpy as np

import dvi


def main():
    one = np.ones((1, 1))
    lcs = dvi.Lcs(A=-one, B=one, C=one, D=0 * one, p=[-1.0])
    run = dvi.integrate_event(lcs, x0=[1.0], t0=0.0, t_end=2.0, rtol=1e-10)
    print(run.report(full=True), end="")
    if not run.succeeded or len(run.events) != 1:
        return 1, None
    clamp = run.event_times[0]
    error = abs(clamp - math.log(2.0))
    print(f"diode clamps at t = {clamp:.17g} (ln 2 to {error})")
    return (0 if error < 1e-8 else 1), clamp  # CVODE's error test at rtol 1e-10, 100x slack


if __name__ == "__main__":
    raise SystemExit(main()[0])
