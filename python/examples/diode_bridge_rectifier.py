# SPDX-License-Identifier: Apache-2.0
"""Siconos' tutorial diode bridge rectifier integrated with dvi's θ
time-stepping ([Seed] scheme (7.2)), the twin of
examples/diode_bridge_rectifier.cpp. With ideal diodes the LC tank always
sees the load R, so the exact answer is a damped RLC oscillation: the error
of backward Euler (θ = 0, γ = 1) and of the trapezoidal weighting
(θ = γ = ½) as h shrinks, first against second order; exits non-zero if
either order is off."""
import math

import numpy as np

import dvi

L, C, R, V0, I0 = 1e-2, 1e-6, 1e3, 10.0, 0.0  # 10 mH, 1 µF, 1 kΩ, 10 V
T_END = 5e-3


def diode_bridge():
    """examples/circuits/diode_bridge.cpp's LCS: λ = (−v_DR1, −v_DF2, i_DF1,
    i_DR2), w = (i_DR1, i_DF2, −v_DF1, −v_DR2)."""
    A = np.array([[0.0, -1 / C], [1 / L, 0.0]])
    B = np.array([[0.0, 0.0, -1 / C, 1 / C], [0.0, 0.0, 0.0, 0.0]])
    Cmat = np.array([[0.0, 0.0], [0.0, 0.0], [-1.0, 0.0], [1.0, 0.0]])
    D = np.array([[1 / R, 1 / R, -1, 0], [1 / R, 1 / R, 0, -1], [1, 0, 0, 0], [0, 1, 0, 0]],
                 dtype=float)
    return dvi.Lcs(A=A, B=B, C=Cmat, D=D)


def exact_v(t):
    """v_C(t) of x' = M x, M = [[−1/(RC), −1/C], [1/L, 0]] (underdamped here):
    exp(Mt) = e^{−αt}[cos ωt I + sin(ωt)/ω (M + αI)], α = 1/(2RC)."""
    alpha = 1 / (2 * R * C)
    omega = math.sqrt(1 / (L * C) - alpha * alpha)
    c, s = math.cos(omega * t), math.sin(omega * t) / omega
    return math.exp(-alpha * t) * (c * V0 + s * ((-1 / (R * C) + alpha) * V0 - I0 / C))


def max_voltage_error(h, theta, gamma):
    run = dvi.integrate_stepping(diode_bridge(), [V0, I0], 0.0, T_END, h=h, theta=theta,
                                 gamma=gamma)
    if not run.succeeded:
        raise SystemExit(f"integration failed: {run.message}")
    return max(abs(x[0] - exact_v(t)) for t, x in zip(run.times, run.states))


def main():
    """(0 if both orders are as expected, the rows (scheme, h, error))."""
    rows, orders_as_expected = [], True
    for name, theta, gamma, expected in [("theta = 0, gamma = 1", 0.0, 1.0, 1.0),
                                         ("theta = gamma = 1/2", 0.5, 0.5, 2.0)]:
        print(f"{name}\n        h      max |v - v_exact| [V]   order")
        previous = math.nan
        for h in (4e-6, 2e-6, 1e-6, 5e-7):
            error = max_voltage_error(h, theta, gamma)
            order = math.log2(previous / error)
            print(f"  {h:8.1e}   {error:23.17g}   {order:5.2f}")
            if not math.isnan(previous) and abs(order - expected) > 0.3:
                orders_as_expected = False
            rows.append((name, h, error))
            previous = error
    return (0 if orders_as_expected else 1), rows


if __name__ == "__main__":
    raise SystemExit(main()[0])
