"""How sharp a design is (runtime/design/sharpness.py): the objective at +- a maker's tolerance of
each varied key, the knife-edge verdict, and the ridge of keys that act on the hover state alike."""
from __future__ import annotations

import numpy as np
import pytest

import levitron as lev
from levitron.runtime.design import sharpness as sh
from levitron.runtime.design.launch_design import FRESH, odds_at
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.errors import UserError
from levitron.runtime.physics.stability.analysis import stability_of
from levitron.runtime.ui.human import Units


def test_spin_range_sharpness_is_the_float_routes_window_at_plus_and_minus_the_tolerance():
    study = lev.load("thesis_stable")
    tol = 5e-5
    res = study.optimize("spin-range", {"top.mass": (0.0505, 0.0524)}, tolerance={"top.mass": tol})
    block = res.sharpness["keys"]["top.mass"]
    m = res.optimum["top.mass"]
    width = []
    for mass in (m - tol, m + tol):          # independent: the discriminant route of `stability`
        lo, hi = stability_of(study.model, mass=mass, eigen=False).spin_interval
        width.append(hi - lo)
    assert block["tolerance"] == tol
    assert block["at_minus"] == pytest.approx(width[0], rel=1e-9)
    assert block["at_plus"] == pytest.approx(width[1], rel=1e-9)
    assert block["sensitivity"] == pytest.approx((width[1] - width[0]) / (2 * tol), rel=1e-9)
    assert block["knife_edge"] == (min(width) < 0.9 * res.value)
    assert res.as_json()["sharpness"] == res.sharpness
    assert res.sharpness["ridge"] is None                 # one key: no ridge


def test_the_verdict_reads_the_loss_on_either_side():
    assert sh.knife_edge(0.55, 0.03, 0.08, launch=True)           # the user's 55 % -> 3-8 %
    assert not sh.knife_edge(0.55, 0.50, 0.54, launch=True)
    assert sh.knife_edge(0.55, 0.54, 0.27, launch=True)           # one side loses more than half
    assert not sh.knife_edge(0.55, 0.28, 0.54, launch=True)
    assert sh.knife_edge(2000.0, 2000.0, 1799.0, launch=False)    # more than 10 %
    assert not sh.knife_edge(2000.0, 1801.0, 1990.0, launch=False)
    assert sh.knife_edge(2000.0, None, 1990.0, launch=False)      # no hover on one side


def test_a_synthetic_sharp_objective_is_a_knife_edge_and_a_flat_one_is_not():
    sharp = sh.probe(lambda x: float(np.exp(-((x[0] - 1.0) / 1e-4) ** 2)), {"k": 1.0}, 1.0, {"k": 1e-4}, True)
    flat = sh.probe(lambda x: float(np.exp(-((x[0] - 1.0) / 1e-1) ** 2)), {"k": 1.0}, 1.0, {"k": 1e-4}, True)
    assert sharp["k"]["knife_edge"] and sharp["k"]["at_minus"] == pytest.approx(np.exp(-1))
    assert not flat["k"]["knife_edge"]
    lines = sh.sharpness_lines({"objective": 1.0, "keys": sharp, "ridge": None}, Units(si=True))
    assert lines[0].startswith("a knife edge: k +-")
    assert "takes the odds to 36.8 %" in lines[0]


def test_two_parallel_columns_are_one_ridge_and_the_null_direction_is_their_difference():
    J = np.array([[1.0, 2.0], [0.5, 1.0], [0.1, 0.2 + 1e-3]])
    r = sh.ridge(["plate.r_in", "plate.thickness"], J)
    assert [p["keys"] for p in r["one_ridge"]] == [["plate.r_in", "plate.thickness"]]
    d = np.array(list(r["direction"].values()))
    assert np.linalg.norm(J @ d) < 1e-3 * np.linalg.norm(J)
    assert sh.ridge(["a", "b"], np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]))["one_ridge"] == []
    keys = {k: {"tolerance": 1e-4, "at_minus": 1.0, "at_plus": 1.0, "knife_edge": False} for k in r["direction"]}
    lines = sh.sharpness_lines({"objective": 1.0, "keys": keys, "ridge": r}, Units(si=True))[2:]
    assert lines[0].startswith("plate.r_in and plate.thickness move along one ridge")


def test_the_moment_and_the_remanence_of_the_toy_set_one_field_so_one_ridge():
    """mu and the plate's remanence enter only as mu B (thesis 2.2.11): exactly parallel; the
    block thickness, which also just sets the field at the hover height, within a few degrees."""
    model = lev.load("levitron_toy").model
    opt = {"top.moment": -0.65, "plate.remanence": 0.1568515, "plate.thickness": 0.02}
    varies = [Vary(k, v * 0.9, v * 1.1) if v > 0 else Vary(k, v * 1.1, v * 0.9) for k, v in opt.items()]
    block = sh.sharpness(lambda x: 1.0, model, varies, opt, 1.0, None, launch=False)
    pairs = {tuple(p["keys"]): p["angle_deg"] for p in block["ridge"]["one_ridge"]}
    assert pairs[("top.moment", "plate.remanence")] < 1e-3
    assert pairs[("plate.remanence", "plate.thickness")] < 10
    d = block["ridge"]["direction"]
    assert d["top.moment"] == pytest.approx(d["plate.remanence"], rel=1e-4)    # one tolerance each way
    text = "\n".join(sh.sharpness_lines(block, Units(si=True), model.scene))
    assert "top.moment, plate.remanence and plate.thickness move along one ridge" in text


def test_default_tolerances_follow_the_keys_units_and_a_given_one_is_checked():
    scene = lev.load("levitron_toy").scene
    assert sh.default_tolerance(scene, "plate.hole", 0.005) == 1e-4            # 0.1 mm
    assert sh.default_tolerance(scene, "top.mass", 0.02) == 1e-4               # 0.1 g
    assert sh.default_tolerance(scene, "plate.remanence", 0.15) == pytest.approx(1.5e-3)   # 1 %
    assert sh.default_tolerance(scene, "top.A", 1.3e-6) == pytest.approx(0.002 * 1.3e-6)
    assert sh.parse_tolerance(["plate.hole=0.0005"]) == {"plate.hole": 0.0005}
    with pytest.raises(UserError, match="not a «vary» key"):
        sh.tolerances(scene, {"plate.hole": 0.005}, {"plate.side": 1e-3})
    with pytest.raises(UserError, match="positive"):
        sh.tolerances(scene, {"plate.hole": 0.005}, {"plate.hole": -1e-3})
    with pytest.raises(UserError, match="KEY=VALUE"):
        sh.parse_tolerance(["plate.hole"])


def test_launch_odds_sharpness_is_the_odds_on_the_optimums_fresh_draws():
    study = lev.load("thesis_air")
    res = study.optimize("launch-odds", {"top.mass": (0.0505, 0.0524)}, n=16, t_end=2.0, workers=1,
                         tolerance={"top.mass": 3e-4})
    block = res.sharpness["keys"]["top.mass"]
    assert res.sharpness["objective"] == res.probability
    from levitron.runtime.scan.launch_odds import Request
    fresh = Request(res.inputs, res.n, res.seed + FRESH, res.success_time, res.t_end, workers=1)
    m = res.optimum["top.mass"]
    assert block["at_minus"] == odds_at(study.model.ref, ["top.mass"], [m - 3e-4], fresh)["probability"]
    assert block["at_plus"] == odds_at(study.model.ref, ["top.mass"], [m + 3e-4], fresh)["probability"]
    assert res.as_json()["sharpness"]["keys"]["top.mass"]["tolerance"] == 3e-4
