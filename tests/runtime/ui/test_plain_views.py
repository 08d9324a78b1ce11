"""What the plain views say beside their answer: the vertical stiffness (which `optimize
--constrain stiffness>=K` speaks of) in `equilibrium` and `stability`; `--fit-height --param` takes
scene keys as --vary does; `--write-scene` says where it wrote; `optimize --help` lists every
objective."""
from __future__ import annotations

import json

import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.design.optimize import OBJECTIVES


def _out(capsys, *argv) -> str:
    assert cli.main(list(argv)) == 0
    return capsys.readouterr().out


def _json(capsys, *argv) -> dict:
    return json.loads(_out(capsys, *argv, "--json"))


def test_stiffness_in_the_plain_views(capsys):
    st = _json(capsys, "stability", "thesis_stable")
    out = _out(capsys, "stability", "thesis_stable")
    assert f"vertical stiffness there: U'' = mu Phi_3 = {st['stiffness']:.4g} N/m (thesis 3.3.3)" in out
    eq = _json(capsys, "equilibrium", "thesis_stable")
    stable = [e for e in eq["equilibria"] if e["vertically_stable"]][0]
    assert stable["stiffness"] == pytest.approx(st["stiffness"], rel=1e-9)
    out = _out(capsys, "equilibrium", "thesis_stable")
    assert f"vertical stiffness U'' = mu Phi_3 (thesis 3.3.3): {stable['stiffness']:.4g} N/m at 10.65 cm" in out


def test_fit_height_takes_scene_keys(capsys):
    """--param plate.murho solves for the scene key itself and agrees with the moment route's
    product; ring_magnet's remanence is fitted in T as the scene writes it."""
    by_key = _json(capsys, "optimize", "thesis", "--fit-height", "0.09", "--param", "plate.murho")
    by_mu = _json(capsys, "optimize", "thesis", "--fit-height", "0.09")
    assert by_key["optimum"]["plate.murho"] == pytest.approx(by_mu["optimum"]["murho"], rel=1e-10)
    ring = _json(capsys, "optimize", "ring_magnet", "--fit-height", "0.07", "--param", "plate.remanence")
    assert 0.3 < ring["optimum"]["plate.remanence"] < 0.5
    z = [e["z"] for e in ring["equilibria"] if e["vertically_stable"]]
    assert z == [pytest.approx(0.07, rel=1e-8)]


def test_fit_height_unknown_param_names_both_kinds(capsys):
    assert cli.main(["optimize", "thesis", "--fit-height", "0.09", "--param", "bogus"]) == 2
    err = capsys.readouterr().err
    assert "scene key" in err and "plate_rho" in err


def test_write_scene_says_where(tmp_path, capsys):
    target = tmp_path / "best.toml"
    out = _out(capsys, "optimize", "thesis_stable", "--maximize", "spin-range", "--vary",
               "top.mass=0.0505:0.0524", "--constrain", "stiffness>=0.5", "--write-scene", str(target))
    assert target.is_file() and f"scene written: {target}" in out


def test_optimize_help_lists_every_objective(capsys):
    with pytest.raises(SystemExit):
        cli.main(["optimize", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for name in OBJECTIVES:
        assert name in text


UNIT_RING = """name = "unit_ring"
g = 1.0
units = "dimensionless"
[top]
mass = 0.02015
A = 0.01
C = 0.006
moment = -1.0
[plate]
kind = "ring_magnet"
r_out = 1.0
r_in = 0.5
thickness = 0.3
remanence = 1.0
[field]
order = 4
[model]
needs = ["reduced", "full", "linear"]
"""


def test_a_band_above_z_c_and_approximations_out_of_range_say_so(tmp_path, capsys):
    """A ring in its own units whose stable band (1.231-1.237) starts above z_c = 1.099: z_c is
    not called "where the band starts"; the thesis's small-g21 estimates there give sigma_1 above
    sigma_2, which is said, not printed as an interval."""
    path = tmp_path / "unit_ring.toml"
    path.write_text(UNIT_RING)
    eq = _json(capsys, "equilibrium", str(path))
    assert eq["stable_band"]["z"][0] > 1.1 * eq["z_c"]
    out = _out(capsys, "equilibrium", str(path))
    assert "where the band starts" not in out and "(the heaviest top's height, below the band)" in out
    assert "(where the band starts)" in _out(capsys, "equilibrium", "thesis")
    st = _json(capsys, "stability", str(path))
    ap = st["approximations"]
    assert ap["sigma1"] > ap["sigma2"]
    out = _out(capsys, "stability", str(path))
    assert "the thesis's approximations (eqs. 3.3.22/3.3.23) do not apply" in out
    assert f"{ap['sigma1']:.4g}-{ap['sigma2']:.4g}" not in out


def test_launch_inputs_in_the_scene_units():
    """`launch`'s line of inputs: each distribution with its unit (the JSON keeps the SI specs);
    relative spreads in percent; a dimensionless scene's lengths and speeds bare."""
    from levitron.runtime.cli.commands.launch import launch_input
    from levitron.runtime.ui.human import Units
    si, dl = Units(si=True), Units(si=False)
    assert launch_input("spin", "normal:1122.18,112.218", si) == "spin 1122 rad/s, sd 112.2 rad/s (normal)"
    assert launch_input("offset", "normal:0,0.00106467", si) == "offset 0 m, sd 1.065 mm (normal)"
    assert launch_input("velocity", "normal:0,0.0102198", si) == "velocity 0 m/s, sd 0.01022 m/s (normal)"
    assert launch_input("mass", "rel:normal:-0.001,0.002", si) == "mass -0.1 %, sd 0.2 % (normal)"
    assert launch_input("strength", "rel:normal:0,0.005", si) == "strength +0 %, sd 0.5 % (normal)"
    assert launch_input("tilt", "uniform:0,0.02", si) == "tilt 0 rad to 0.02 rad (uniform)"
    assert launch_input("temperature", "28", si) == "temperature 28 degC"
    assert launch_input("velocity", "normal:0,0.0102198", dl) == "velocity 0, sd 0.01022 (normal)"
    assert launch_input("offset", "uniform:-0.01,0.01", dl) == "offset -0.01 to 0.01 (uniform)"
    assert launch_input("spin", "normal:60,6", dl) == "spin 60 rad/time, sd 6 rad/time (normal)"


def test_a_range_of_lengths_in_one_unit():
    """A height range takes the unit of its larger end, as a single height does: a millimetre top's
    band reads '1-1.319 mm' beside its '1.242 mm' hover height, not '0.1-0.1319 cm'."""
    from levitron.runtime.ui.human import Units
    from levitron.runtime.ui.plain_text import shown
    si = Units(si=True)
    assert si.length_span(0.0994827, 0.110185) == "9.948-11.02 cm"
    assert si.length_span(0.001, 0.0013186) == "1-1.319 mm"
    assert si.length_span(0.35, 1.2) == "0.35-1.2 m"
    assert Units(si=False).length_span(0.001, 0.0013186) == "0.001-0.001319"
    assert shown("outside the band ‹[0.001, 0.0013186]|m›", si) == "outside the band 1-1.319 mm"


@pytest.mark.parametrize("scene, shown", [
    ("thesis", "plate_a 10 cm, plate_w 3 cm, plate_rho 0.00262094 T m"),
    ("square", "plate_thickness 2 cm, plate_magnetization 310352 A/m"),
    ("loop", "plate_a 5 cm, plate_current 795.775 A"),
])
def test_info_shows_each_plate_parameter_with_its_unit(capsys, scene, shown):
    assert shown in _out(capsys, "info", scene)


def test_launch_shows_a_temperature_that_matters():
    """The launches' temperature is shown where it is spread or the magnets have a temperature
    coefficient (thesis_air), not as a fixed 20 degC that changes nothing (thesis_stable)."""
    from levitron.scene.load import load_scene
    from levitron.runtime.cli.commands.launch import _temperature_matters
    assert _temperature_matters("20", load_scene("thesis_air"))
    assert not _temperature_matters("20", load_scene("thesis_stable"))
    assert _temperature_matters("normal:20,2", load_scene("thesis_stable"))


def test_a_dimensionless_restatement_drops_every_si_unit_the_views_know():
    """A quantity's unit is one of SI_SYMBOLS (the plate units A/m and T m included): a runtime
    sentence about a dimensionless scene, rendered by runtime/ui/plain_text.py, keeps none of them."""
    from levitron.runtime.ui.human import Units
    from levitron.runtime.ui.plain_text import shown
    dl = Units(si=False)
    assert shown("M = ‹310352|A/m› and rho = ‹0.0026|T m› at ‹0.5|m/s›", dl) == "M = 310352 and rho = 0.0026 at 0.5"
