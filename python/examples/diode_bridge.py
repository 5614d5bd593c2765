# SPDX-License-Identifier: Apache-2.0
"""The diode bridge rectifier's picture (README's docs/images/diode_bridge.png)
from Python: examples/scenes/diode_bridge.json's LCS under the automatic
driver, the tank states and the four diode multipliers, mode switches dashed.

    PYTHONPATH=build/python python3 python/examples/diode_bridge.py out.png

Needs matplotlib (Debian python3-matplotlib)."""
import json
import pathlib
import sys

import numpy as np

import dvi

SCENE = pathlib.Path(__file__).resolve().parents[2] / "examples/scenes/diode_bridge.json"


def run_bridge(samples=1001):
    scene = json.loads(SCENE.read_text())
    p = scene["problem"]
    lcs = dvi.Lcs(A=np.array(p["A"]), B=np.array(p["B"]), C=np.array(p["C"]), D=np.array(p["D"]))
    horizon = scene["horizon"]
    method = scene["method"]
    return dvi.integrate_auto(lcs, scene["x0"], 0.0, horizon,
                              output_times=list(np.linspace(0.0, horizon, samples)),
                              h=method["h"], theta=method["theta"], gamma=method["gamma"])


def main(path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    run = run_bridge()
    if not run.succeeded:
        raise SystemExit(run.message)
    figure, (upper, lower) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    for k, name in enumerate(["v_C (V)", "i_L (A)"]):
        upper.plot(run.times, run.states[:, k], label=name)
    for k in range(run.multipliers.shape[1]):
        lower.plot(run.times, run.multipliers[:, k], label=f"u{k + 1}")
    for t in np.unique(run.event_times):
        for axes in (upper, lower):
            axes.axvline(t, color="grey", linestyle="--", linewidth=0.5)
    upper.set_title("diode bridge: " + run.report())
    upper.legend()
    lower.legend()
    lower.set_xlabel("t (s)")
    figure.savefig(path)
    print(f"{path}: {len(run.times)} samples, {len(run.events)} events")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "diode_bridge.png")
