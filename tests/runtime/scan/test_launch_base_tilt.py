"""The launch odds over a base that is not level (issue 27; runtime/scan/launch_inputs.py APPARATUS):
`launch --base-tilt DIST` sets each sample's runtime parameter base_tilt, the launch aimed at the
level hover point.

Checked against independent routes: at a fixed base tilt of 0 the tilted model's launches are the
level model's (another generated model, the same seed) launch for launch; beyond the scene's
max_base_tilt (`stability --level-tolerance`: the fold of the equilibrium, where no relative
equilibrium is left) no launch floats, while well below it most do; with the base tilt the only
spread, the ranking names it and every launch above the fold fails.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import levitron as lev
from levitron.runtime.cli.main import main
from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_inputs as li
from levitron.runtime.scan import launch_summary as ls

SCENE = "thesis_stable"                  # no air: runs of three slow periods (10.8 s)
TILTED = {"plate.tilt": 0.0}             # the tilted model, level as written
SPIN = "normal:1100,110"                 # given: the default spin is each model's own interval's
THE_TOP = {"mass": "rel:0", "strength": "rel:0"}   # the scene's own top: its own max_base_tilt


@pytest.fixture(scope="module")
def tilted():
    return lev.load(SCENE, TILTED)


@pytest.fixture(scope="module")
def max_base_tilt(tilted):
    from levitron.runtime.physics.apparatus.tilted_stability import level_tolerance
    tol = level_tolerance(tilted.model, tilted.model.p)
    assert tol["limited_by"] == "fold" and tol["max_base_tilt"] == tol["fold_tilt"]
    return tol["max_base_tilt"]


def test_a_fixed_base_tilt_of_zero_is_the_level_launch_launch_for_launch(tilted):
    """The apparatus inputs are drawn after the launch's own, so the same seed draws the same
    launches; at base_tilt 0 the tilted model's gravity is the level one's, so every launch ends
    the same way. The two models are different generated code (the tilt's terms), so the times a
    falling top leaves its box agree to rounding, not bit for bit: measured 2.9e-9 s in 10.8 s."""
    n = 40
    level = lev.load(SCENE).launch(n=n, seed=3, inputs={"spin": SPIN})
    zero = tilted.launch(n=n, seed=3, inputs={"spin": SPIN, "base_tilt": 0.0})
    a, b = level.launches, zero.launches
    assert "base_tilt" not in a and np.all(b["base_tilt"] == 0.0)
    for k in a:
        if k != "flight_time":
            assert np.array_equal(a[k], b[k]), k
    assert np.max(np.abs(a["flight_time"] - b["flight_time"])) <= 1e-8 * level.success_time
    assert 0 < level.probability < 1 and zero.probability == level.probability
    assert zero.details["inputs"]["base_tilt"] == "0.0"
    assert "base_tilt" not in zero.details["defaulted"] and "base_tilt_azimuth" in zero.details["defaulted"]
    assert zero.details["inputs"]["base_tilt_azimuth"] == "0.0"      # no direction of a level base
    assert "base_tilt_azimuth" not in [e["input"] for e in zero.details["ranking"]]


def test_beyond_max_base_tilt_nothing_floats_and_well_below_most_do(tilted, max_base_tilt):
    """Past the fold the top has no equilibrium to find (level_tolerance; thesis_stable's own top:
    mass and strength fixed, since a lighter or weaker top hovers elsewhere, with a tolerance of its
    own): every launch falls, within a few seconds. Well below it, most launches float: the base
    tilt reaches the model as a sample's own, not as a refusal of every launch."""
    beyond = tilted.launch(n=30, seed=1, inputs={"spin": SPIN, "base_tilt": 1.05 * max_base_tilt, **THE_TOP})
    assert beyond.details["successes"] == 0 and beyond.details["outcomes"] == {"left_box": 30}
    assert np.all(beyond.launches["base_tilt"] == 1.05 * max_base_tilt)
    assert np.max(beyond.launches["flight_time"]) < 0.5 * beyond.success_time
    below = tilted.launch(n=30, seed=1, inputs={"spin": SPIN, "base_tilt": 0.1 * max_base_tilt, **THE_TOP})
    assert below.probability > 0.6


def test_the_ranking_names_the_base_tilt_when_it_is_the_only_spread(tilted, max_base_tilt):
    """Spin, tilt, offset, velocity, mass and strength fixed (tilt, offset and velocity 0: without
    the base's tilt every launch would lie on the invariant set, which is refused; the base's tilt
    moves the equilibrium off the launch point, so it is not); the base tilt uniform up to twice
    the fold: the ranking has the base tilt alone, beyond its noise, and no launch above the fold
    floats."""
    fixed = {"spin": 1100.0, "tilt": 0.0, "tilt_azimuth": 0.0, "offset": 0.0, "velocity": 0.0, **THE_TOP,
             "base_tilt_azimuth": 0.0}
    with pytest.raises(UserError, match="invariant set"):
        tilted.launch(n=5, inputs={**fixed, "base_tilt": 0.0})
    r = tilted.launch(n=60, seed=2, inputs={**fixed, "base_tilt": f"uniform:0,{2 * max_base_tilt!r}"})
    ranking = r.details["ranking"]
    assert [e["input"] for e in ranking] == ["base_tilt"]
    assert ranking[0]["effect"] > ranking[0]["noise"]
    t = r.launches
    assert np.all(t["floats"][t["base_tilt"] > max_base_tilt] == 0)
    assert np.mean(t["floats"][t["base_tilt"] < 0.3 * max_base_tilt]) == 1.0
    assert ranking[0]["success_rate"][0] == 1.0 and ranking[0]["success_rate"][-1] == 0.0


def test_a_scene_without_the_tilted_model_is_refused_in_one_line(capsys, tmp_path):
    assert main(["launch", SCENE, "--base-tilt", "normal:0,0.0005", "--n", "5"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--set plate.tilt=0" in err and "plate.tilt" in err
    with pytest.raises(UserError, match=r"plate\.tilt=0"):
        lev.load(SCENE).launch(n=5, inputs={"base_tilt_azimuth": 0.3})
    scene = tmp_path / "crooked.toml"        # the [launch] table's key is refused alike
    from levitron.scene.paths import SCENES_DIR
    scene.write_text((SCENES_DIR / f"{SCENE}.toml").read_text() + '\n[launch]\nbase_tilt = "normal:0,0.001"\n')
    assert main(["launch", str(scene), "--n", "5"]) == 2
    assert "--set plate.tilt=0" in capsys.readouterr().err


def test_the_command_line_takes_the_base_tilt_and_saves_it(tmp_path, capsys):
    save = tmp_path / "launches.csv"
    assert main(["launch", SCENE, "--set", "plate.tilt=0", "--base-tilt", "uniform:0,0.0005",
                 "--spin", SPIN, "--n", "8", "--save", str(save), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["inputs"]["base_tilt"] == "uniform:0.0,0.0005"
    assert r["inputs"]["base_tilt_azimuth"] == f"uniform:0.0,{2 * math.pi!r}"
    assert list(r["saved"]["columns"])[9:11] == ["base_tilt", "base_tilt_azimuth"]
    assert r["saved"]["columns"]["base_tilt"] == "rad"
    units, *rows = save.read_text().splitlines()         # the units' comment line first
    head = rows[0].split(",")
    assert ", base_tilt=rad, base_tilt_azimuth=rad, " in units
    tilts = [float(row.split(",")[head.index("base_tilt")]) for row in rows[1:]]
    assert len(tilts) == 8 and all(0 <= t <= 0.0005 for t in tilts) and len(set(tilts)) == 8
    assert main(["launch", SCENE, "--set", "plate.tilt=0", "--base-tilt", "uniform:0,0.0005",
                 "--spin", SPIN, "--n", "8"]) == 0
    out = capsys.readouterr().out
    assert "base_tilt 0 rad to 0.0005 rad (uniform)" in out
    with pytest.raises(SystemExit):
        main(["launch", "--help"])
    assert "--base-tilt DIST" in capsys.readouterr().out


def test_apparatus_inputs_are_entries():
    """The apparatus inputs come after the launch's own (their draws after theirs), each naming
    the runtime parameter it sets and the scene key that adds the term."""
    assert li.ALL_INPUTS[:len(li.INPUTS)] == li.INPUTS
    assert [(a.name, a.param, a.scene_key) for a in li.APPARATUS] == [
        ("base_tilt", "base_tilt", "plate.tilt"), ("base_tilt_azimuth", "base_tilt_azimuth", "plate.tilt"),
        ("moment_tilt", "moment_tilt", "top.moment_tilt")]
    assert all(li.INPUT_UNITS[a.name] == a.unit == ls.LAUNCH_UNITS[a.name] for a in li.APPARATUS)
