# SPDX-License-Identifier: Apache-2.0
"""dvi.Scene: scenes from a JSON file or a dict, run as `dvisim run` runs
them. Against a scene's exact block, against dvisim's own files of the same
scene (trajectory.csv byte for byte, summary.json field for field), and
malformed scenes raising dvisim's message, which names the field."""
import copy
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import dvi

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "examples" / "scenes"
DVISIM = os.environ.get("DVISIM")

# A build with dvisim (which CTest passes as DVISIM) has dvi.Scene.
needs_scenes = pytest.mark.skipif(not hasattr(dvi, "Scene") and DVISIM is None,
                                  reason="module built without dvisim's scene reader")
needs_dvisim = pytest.mark.skipif(DVISIM is None, reason="DVISIM (the dvisim binary) not set")

# Event-driven at rtol 1e-10, atol 1e-12: CVODE's global error stays within
# about 100 rtol (test_integrators.py's EVENT_TOLERANCE, same reason).
EVENT_TOLERANCE = 1e-8
# summary.json fields that measure the run's wall-clock time, not its answer.
TIMING_FIELDS = {"wall_seconds", "seconds"}


def without_timing(value):
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items() if k not in TIMING_FIELDS}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


def dvisim_run(scene_path, out_dir, *flags):
    return subprocess.run([DVISIM, "run", str(scene_path), "--out", str(out_dir), *flags],
                          capture_output=True, text=True, check=False)


@needs_scenes
def test_saturation_matches_its_exact_block():
    scene = dvi.Scene.from_json(str(SCENES / "dvi_saturation.json"))
    assert (scene.name, scene.type, scene.n, scene.horizon) == ("dvi-saturation", "box-dvi", 1, 4.0)
    assert scene.has_exact
    run = scene.run(method="event", rtol=1e-10, atol=1e-12)
    trajectory = run.trajectory
    assert trajectory.succeeded, trajectory.message
    # The bound leaves at x = 1, t = 2 (x = 3 - t): one event there.
    assert np.abs(trajectory.event_times - 2.0).min() < EVENT_TOLERANCE
    exact = np.array([scene.exact(t) for t in trajectory.times])
    assert np.abs(trajectory.states - exact).max() < EVENT_TOLERANCE
    # The output grid is the scene's: 41 samples and the times 1, 2, 3.
    assert set(scene.output_times) <= set(trajectory.times)
    assert [i["method"] for i in trajectory.intervals] == ["event"]


# Every form the scene runner distinguishes: a box DVI stepped, the filippov
# matrix form (u reported as s), a filippov f0/f1/h scene event-driven, an
# LCS circuit by auto, projected dynamics, a boundary-value and a nash scene.
SCENE_RUNS = [
    ("dvi_saturation.json", []),
    ("filippov_sign_matrix.json", []),
    ("filippov_relay.json", ["--method", "event"]),
    ("diode_bridge.json", []),
    ("pds_box.json", []),
    ("periodic_rectifier.json", []),
    ("nash_game.json", []),
]


def overrides(flags):
    return {flags[k].lstrip("-").replace("-", "_"): flags[k + 1] for k in range(0, len(flags), 2)}


@needs_scenes
@needs_dvisim
@pytest.mark.parametrize("name,flags", SCENE_RUNS)
def test_run_equals_dvisim_bit_for_bit(name, flags, tmp_path):
    done = dvisim_run(SCENES / name, tmp_path / "out", *flags)
    assert done.returncode == 0, done.stderr
    run = dvi.Scene.from_json(str(SCENES / name)).run(**overrides(flags))
    assert run.trajectory.succeeded, run.trajectory.message
    assert run.csv == (tmp_path / "out" / "trajectory.csv").read_text()
    written = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert without_timing(run.summary) == without_timing(written)
    # The arrays hold the csv's numbers; at an event they hold both limits,
    # of which the csv keeps one row (the right limit; x⁻ too at a jump).
    table = np.loadtxt(tmp_path / "out" / "trajectory.csv", delimiter=",", skiprows=1, ndmin=2)
    trajectory = run.trajectory
    rows = np.hstack([trajectory.times[:, None], trajectory.states, run.multipliers])
    if table.shape[1] == rows.shape[1]:  # a nash scene's csv adds λ columns
        for row in table:
            same_time = rows[rows[:, 0] == row[0]]
            assert any(np.array_equal(row, r) for r in same_time), row

@needs_scenes
def test_dict_and_file_give_the_same_run():
    text = (SCENES / "diode_bridge.json").read_text()
    from_file = dvi.Scene.from_json(str(SCENES / "diode_bridge.json")).run()
    from_dict = dvi.Scene.from_dict(json.loads(text)).run()
    assert from_dict.csv == from_file.csv


@needs_scenes
def test_filippov_matrix_form_reports_the_sign():
    # x' = 1/2 - sgn(x) from 1: x reaches 0 at t = 2 and slides there with
    # s = 1/2 (Filippov's convexification, paper eq. (4.1)).
    run = dvi.Scene.from_json(str(SCENES / "filippov_sign_matrix.json")).run(
        method="event", rtol=1e-10, atol=1e-12)
    times = run.trajectory.times
    assert np.abs(run.trajectory.states[:, 0] - np.maximum(1 - 0.5 * times, 0)).max() < 1e-8
    sliding = times > 2 + 1e-6
    assert np.abs(run.multipliers[sliding, 0] - 0.5).max() < 1e-8


def broken(edit):
    fields = json.loads((SCENES / "dvi_saturation.json").read_text())
    edit(fields)
    return fields


# Each mistake and the field dvisim names for it.
MISTAKES = [
    (lambda s: s["problem"]["F"].__setitem__(0, "u1 + y"), "problem.F[0]"),
    (lambda s: s.__setitem__("x0", [1, 2]), "x0"),
    (lambda s: s["method"].__setitem__("h", -1), "method.h"),
    (lambda s: s.__setitem__("horizn", 4), "horizn"),
    (lambda s: s["exact"]["pieces"][0].__setitem__("to", 7), "exact"),
]


@needs_scenes
@pytest.mark.parametrize("edit,field", MISTAKES)
def test_malformed_dict_names_the_field(edit, field):
    with pytest.raises(dvi.InvalidInputError, match=field.replace("[", r"\[")):
        dvi.Scene.from_dict(broken(edit))


@needs_scenes
@needs_dvisim
@pytest.mark.parametrize("edit,field", MISTAKES)
def test_malformed_file_raises_dvisims_message(edit, field, tmp_path):
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(broken(edit)))
    done = dvisim_run(path, tmp_path / "out")
    assert done.returncode == 2
    with pytest.raises(dvi.InvalidInputError) as raised:
        dvi.Scene.from_json(str(path))
    assert "dvisim: " + str(raised.value) + "\n" == done.stderr
    assert field in str(raised.value)


@needs_scenes
@needs_dvisim
@pytest.mark.parametrize("keywords,flags", [
    ({"h": -1.0}, ["--h", "-1"]),
    ({"rtol": 0.0}, ["--rtol", "0"]),
    ({"method": "leapfrog"}, ["--method", "leapfrog"]),
])
def test_bad_override_raises_dvisims_message(keywords, flags, tmp_path):
    # h and rtol must be > 0; the methods are auto, stepping, event and bvp.
    path = SCENES / "pds_box.json"
    done = dvisim_run(path, tmp_path / "out", *flags)
    assert done.returncode == 2, done.stderr
    with pytest.raises(dvi.InvalidInputError) as raised:
        dvi.Scene.from_json(str(path)).run(**keywords)
    assert "dvisim: " + str(raised.value) + "\n" == done.stderr


@needs_scenes
def test_missing_file_and_exact_block():
    with pytest.raises(dvi.InvalidInputError, match="no_such.json: cannot open"):
        dvi.Scene.from_json("no_such.json")
    with pytest.raises(dvi.InvalidInputError, match="no exact block"):
        dvi.Scene.from_json(str(SCENES / "diode_bridge.json")).exact(0.0)
