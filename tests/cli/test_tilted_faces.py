"""The commands over a tilted base (issue 27, plate.tilt) beyond stability, simulate and launch:
`scan` starts every run at the top's relative equilibrium off the axis (as `simulate` does) or
refuses where there is none; `report` answers for the tilted base and says which of its parts are
the level base's; `optimize` (fits and interval designs) and `figures` refuse a tilted base in
one line (runtime/physics/apparatus/level_only.py).

Independent routes: a scan point's initial state is simulate's (runtime/simulate/start.py
tilted_start) to rounding; the map's verdicts at the tilted base agree with the eigenvalue
route's interval there; a mass marked "cannot hover" is one where the adiabatic potential's
stationary point (the second route of runtime/physics/apparatus/tilted_equilibrium.py) is gone too.
"""
from __future__ import annotations

import html
import json

import numpy as np
import pytest

from levitron.runtime.cli.main import main
from levitron.runtime.errors import UserError

SCENE = "thesis_stable"


@pytest.fixture(scope="module")
def tilted(derived_model):
    return derived_model(SCENE, "plate.tilt=0.0012")


def test_a_scan_point_starts_where_simulate_starts(tilted):
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.scan.points import point_setup
    from levitron.runtime.simulate import start
    pt = tilted.part("full")
    z_s = hover_height(tilted)
    for spin, tilt in ((1200.0, 0.005), (2100.0, 0.01)):
        su = point_setup(tilted, spin, tilt)
        x0 = start.initial_state(pt, z_s, spin, tilt, 0.0, tilted.p)
        want, note = start.tilted_start(tilted, pt, z_s, spin, x0, tilted.p)
        assert "off the axis" in note
        scale = start.state_scales(pt, z_s, spin, tilted.pvals())
        assert np.max(np.abs(su.x0 - want) / scale) <= 1e-12
        assert abs(su.x0[pt.states.index("x")]) > 2e-3          # 2.76 mm downhill, not on the axis


def test_the_tilted_map_agrees_with_the_tilted_interval(capsys):
    """Spins below, inside and above the eigenvalue route's interval at the tilted equilibrium
    (459.1-2645 rad/s at 0.0012 rad): the runs started there stay up exactly inside."""
    from levitron.runtime.physics.stability.analysis import stability_of
    from levitron.runtime.model.load import load_model
    from levitron.scene.load import load_scene
    over = ["plate.tilt=0.0012"]
    lo, hi = stability_of(load_model(load_scene(SCENE, over))).spin_interval
    spins = [0.8 * lo, 1.2 * lo, (lo * hi) ** 0.5, 0.9 * hi, 1.15 * hi]
    assert main(["scan", SCENE, "--set", over[0], "--spin", f"{spins[0]!r}:{spins[-1]!r}:2",
                 "--tilt", "0.005:0.01:2", "--t-end", "5", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["spin_interval"] == [lo, hi] and "tilted base" in r["linear"]["note"]
    assert r["equilibrium"]["offset"] > 2e-3 and "relative equilibrium" in r["equilibrium"]["start"]
    from levitron.runtime.scan import stability_map as sc
    from levitron.runtime.model.load import load_model as lm
    model = lm(load_scene(SCENE, over))
    res = sc.scan(model, np.array(spins), "tilt", np.array([0.005]), t_end=5.0, quiet=True)
    inside = [lo < s < hi for s in spins]
    assert res.levitating[:, 0].tolist() == inside
    assert main(["scan", SCENE, "--set", over[0], "--spin", "1200:2000:2", "--tilt", "0.005:0.01:2",
                 "--t-end", "2"]) == 0
    assert "every run starts at the top's equilibrium there, 2.758 mm off the axis" in capsys.readouterr().out


def test_a_map_beyond_the_fold_is_refused_and_a_mass_without_equilibrium_cannot_hover(capsys, derived_model):
    assert main(["scan", SCENE, "--set", "plate.tilt=0.002", "--spin", "1200:2000:2",
                 "--tilt", "0.005:0.01:2", "--t-end", "2"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no equilibrium" in err and "level the base" in err
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium, TiltedTop
    masses = [0.0505, 0.0514, 0.0523]
    assert main(["scan", SCENE, "--set", "plate.tilt=0.0016", "--spin", "1200:2000:2", "--mass",
                 f"{masses[0]}:{masses[-1]}:3", "--t-end", "3", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    model = derived_model(SCENE, "plate.tilt=0.0016")
    for j, m in enumerate(r["grid"]["mass"]):
        p = model.with_params({"m": m})
        try:
            TiltedTop(model, p, hover_height(model, p)).adiabatic(0.0016)
            exists = True
        except NoEquilibrium:
            exists = False
        assert [row[j] == "no_hover_height" for row in r["status"]] == [not exists] * 2, m
    assert [row[1] for row in r["status"]] == ["no_hover_height"] * 2       # 51.4 g: none


def test_optimize_and_figures_refuse_a_tilted_base(tmp_path, capsys, tilted, derived_model):
    out = tmp_path / "figs"
    assert main(["figures", SCENE, "--set", "plate.tilt=0.001", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--set plate.tilt=0" in err and not out.exists()
    assert main(["optimize", SCENE, "--set", "plate.tilt=0.001", "--maximize", "spin-range",
                 "--vary", "top.mass=0.05:0.052"]) == 2
    assert "--set plate.tilt=0" in capsys.readouterr().err
    assert main(["optimize", SCENE, "--set", "plate.tilt=0.001", "--fit-height", "0.1",
                 "--param", "top.mass"]) == 2
    assert "level base" in capsys.readouterr().err
    from levitron.runtime.physics.apparatus.level_only import refuse_tilted
    with pytest.raises(UserError):
        refuse_tilted(tilted, "x")
    refuse_tilted(derived_model(SCENE, "plate.tilt=0"), "x")      # the level base is answered
    refuse_tilted(derived_model(SCENE), "x")


def test_the_report_answers_for_the_tilted_base_and_says_what_is_level(tmp_path, capsys):
    page = tmp_path / "r.html"
    assert main(["report", SCENE, "--set", "plate.tilt=0.001", "--out", str(page), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    eq = r["tilted_base"]["equilibrium"]
    assert eq["tilt"] == 0.001 and 2e-3 < eq["offset"] < 2.4e-3
    assert r["z_s"] == eq["position"][2]
    assert r["tilted_base"]["level_base"] == ["equilibria and the stable band", "the set-up drawing"]
    text = html.unescape(page.read_text())
    assert "The base is tilted by 0.001 rad" in text and "are the level base's (on the axis)" in text
