#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Writes the `exact` blocks of clamp.json, forced.json and bridge.json, whose
switch times solve transcendental equations, to 17 significant digits (mpmath at
50 digits: Newton from brackets found by scanning the closed forms).
  python3 bench/work_precision/scenes/exact_blocks.py   (rewrites the files in place)
"""
import json
import os

import mpmath as mp

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))


def number(value):
    return float(mp.nstr(value, 17))


def text(value):
    return mp.nstr(value, 17)


def bisect(g, lo, hi):
    return mp.findroot(g, (lo, hi), solver="anderson")


def clamp_pieces(horizon):
    """v' = u - v, 0 <= u _|_ v - sin t >= 0 from v = 0 (RC = omega = 1):
    v = sin t until u = v + v' = sin t + cos t reaches 0 at 3 pi/4 + 2 pi k,
    then v_off exp(t_off - t) until it meets sin t again."""
    pieces, k = [], 0
    while True:
        off = 3 * mp.pi / 4 + 2 * mp.pi * k
        if off >= horizon:
            pieces.append({"x": ["sin(t)"]})
            return pieces
        pieces.append({"to": number(off), "x": ["sin(t)"]})
        v_off = mp.sin(off)
        gap = lambda t: v_off * mp.exp(off - t) - mp.sin(t)
        on = bisect(gap, 2 * mp.pi * (k + 1), 2 * mp.pi * (k + 1.25))
        decay = ["%s*exp(%s - t)" % (text(v_off), text(off))]
        if on >= horizon:
            pieces.append({"x": decay})
            return pieces
        pieces.append({"to": number(on), "x": decay})
        k += 1


def forced_pieces(a, horizon):
    """x' = u, u in SOL([-1, 1], u + x - a sin t), x(0) = 0: free (x' = a sin t
    - x) while |a sin t - x| < 1, x = x_s +- (t - t_s) at a bound until a sin t
    - x returns inside."""
    particular = lambda s: a / 2 * (mp.sin(s) - mp.cos(s))
    pieces, start, mode, x_start = [], mp.mpf(0), 0, mp.mpf(0)
    while True:
        if mode == 0:
            c = x_start - particular(start)
            x = lambda t, c=c, s=start: c * mp.exp(-(t - s)) + particular(t)
            formula = "%s*exp(-t) + %s*(sin(t) - cos(t))" % (text(c * mp.exp(start)), text(a / 2))
            g = lambda t: 1 - abs(a * mp.sin(t) - x(t))
        else:
            x = lambda t, m=mode, s=start, x0=x_start: x0 + m * (t - s)
            formula = "%s %s t" % (text(x_start - mode * start), "+" if mode > 0 else "-")
            g = lambda t, m=mode: m * (a * mp.sin(t) - x(t)) - 1
        end, scan = start + mp.mpf("1e-3"), mp.mpf("1e-3")
        while end < horizon and g(end) > 0:
            end += scan
        if end >= horizon:
            pieces.append({"x": [formula]})
            return pieces
        t = bisect(g, max(end - scan, start + mp.mpf("1e-30")), end)
        pieces.append({"to": number(t), "x": [formula]})
        x_start = x(t)
        mode = 0 if mode != 0 else (1 if a * mp.sin(t) - x_start > 0 else -1)
        start = t


def bridge_pieces(horizon):
    """The ideal diode bridge from (v, i) = (10 V, 0), L = 10 mH, C = 1 uF,
    R = 1 kOhm: one damped oscillation x = exp(-a t)(cos(w t) x0 + sin(w t)/w
    (M + a I) x0), a = 1/(2RC), w^2 = 1/(LC) - a^2 (Cayley-Hamilton, as
    circuits::DiodeBridgeExactState); a diode pair switches where v = 0, at
    tan(w t) = 10 w / 5000."""
    a = mp.mpf(500)
    w = mp.sqrt(mp.mpf(10) ** 8 - a * a)
    formula = ["exp(-a*t)*(10*cos(w*t) - 5000*sin(w*t)/w)", "exp(-a*t)*1000*sin(w*t)/w"]
    pieces, k = [], 0
    while True:
        t = (mp.atan(10 * w / 5000) + k * mp.pi) / w
        if t >= horizon:
            pieces.append({"x": formula})
            return {"a": number(a), "w": number(w)}, pieces
        pieces.append({"to": number(t), "x": formula})
        k += 1


def rewrite(name, pieces, params=None):
    path = os.path.join(HERE, name)
    with open(path) as f:
        scene = json.load(f)
    scene["exact"] = {"pieces": pieces} if params is None else {"params": params, "pieces": pieces}
    with open(path, "w") as f:
        json.dump(scene, f, indent=2)
        f.write("\n")


rewrite("clamp.json", clamp_pieces(10 * mp.pi))
rewrite("forced.json", forced_pieces(mp.mpf(3), mp.mpf(20)))
bridge_params, bridge = bridge_pieces(mp.mpf("5e-3"))
rewrite("bridge.json", bridge, bridge_params)
