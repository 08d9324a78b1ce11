"""`levitron trim` (runtime/design/trim.py, issue 26): the mass by the launch odds, beside the widest
spin window, on the thesis's top in warm air and on a dimensionless scene of its own."""
from __future__ import annotations

import json
import re

import pytest

from levitron.runtime.cli.main import main
from levitron.runtime.design.optimize import optimize
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.design.trim import LIMIT_POINTS
from tests.helpers.trims import trim_with

# the thesis's annulus scaled to g = 1, lengths of 10 cm, masses of 50 g; murho by `optimize
# --fit-height 1.065 --param plate.murho` (the thesis top's 10.65 cm): a stable band 1.007-1.05
DIMLESS = """name = "dimless_annulus"
g = 1.0
units = "dimensionless"
[top]
mass = 1.03
A = 0.0044
C = 0.00264
spin_decay_time = 1500.0
[plate]
kind = "annulus"
radius = 1.0
hole = 0.3
murho = -0.534428
[field]
order = 2
[model]
needs = ["reduced", "full", "linear"]
coordinates = "tait-bryan"
"""
QUICK = ["--n", "40", "--success-time", "20", "--t-end", "20", "--quiet"]


def _run(capsys, *argv):
    assert main(list(argv)) == 0, capsys.readouterr().err
    return capsys.readouterr().out


@pytest.fixture(scope="module")
def warm(tmp_path_factory):
    out = tmp_path_factory.mktemp("trim") / "trim.png"
    return out, ["trim", "thesis_air", "--temperature", "28", *QUICK, "--out", str(out)]


def test_the_trim_beats_the_widest_window_in_warm_air(warm, capsys, derived_model):
    """At 28 degC thesis_air's 51.5 g top is too heavy to hover. The trim's mass floats more launches
    than the mass of the widest linear spin window, whose 95 % intervals do not overlap; that mass is
    the spin-range optimum of `optimize` (IPOPT on the exact route) to one step of the trim's curve;
    the band is `equilibrium`'s."""
    path, argv = warm
    r = json.loads(_run(capsys, *argv, "--json"))
    eq = json.loads(_run(capsys, "equilibrium", "thesis_air", "--temperature", "28", "--json"))
    lo, hi = eq["stable_band"]["mass"]
    assert r["band_mass"] == pytest.approx([lo, hi], rel=1e-12)
    assert r["mass"] == 0.0515 and not lo <= r["mass"] <= hi
    assert lo < r["advice"] < hi and r["change"] == pytest.approx(r["advice"] - r["mass"], rel=1e-12)
    assert r["start_launch_odds"]["probability"] == 0.0
    assert r["launch_odds"]["probability_ci95"][0] > r["widest_window"]["launch_odds"]["probability_ci95"][1]
    model = derived_model("thesis_air", "temperature=28.0")
    best = optimize(model, [Vary("top.mass", lo, hi)], "spin-range", [], 20).optimum["top.mass"]
    assert abs(r["widest_window"]["mass"] - best) < (hi - lo) / (LIMIT_POINTS - 1)
    assert len(r["spin_limits"]) == LIMIT_POINTS and path.stat().st_size > 10_000
    assert "as written it does not float at all" in " ".join(r["warnings"])


def test_the_plain_view_gives_the_change_and_the_odds(warm, capsys):
    text = _run(capsys, *warm[1])
    first = text.splitlines()[0]
    assert re.match(r"take \S+ g off \(to \S+ g\): launch odds 0 % \(it cannot hover\) -> \S+ %", first), first
    assert "the widest spin window" in text and "(defaults: set them with" in text


def test_a_dimensionless_scene_trims_in_its_own_units_and_the_api_agrees(tmp_path, capsys):
    """No SI unit in the plain view of a scene in its own units (the launch spin in rad/time, the
    masses bare); the plot is drawn; Study.trim gives the command's answer, bit for bit."""
    import levitron as lev
    from levitron.runtime.cli.commands.trim import human
    from levitron.runtime.model.scenes import load_scene
    scene = tmp_path / "dimless_annulus.toml"
    scene.write_text(DIMLESS)
    r = json.loads(_run(capsys, "trim", str(scene), *QUICK, "--out", str(tmp_path / "t.png"), "--json"))
    text = human(r, load_scene(str(scene)))
    assert re.search(r"\b(add|take) [\d.e-]+ (off )?\(to [\d.]+\)", text.splitlines()[0]), text
    words = set(re.findall(r"[\d.] ?(kg|g|cm|mm|m|s|rad/s|Hz|rpm|degC)\b", text))
    assert not words, text
    assert (tmp_path / "t.png").stat().st_size > 10_000
    api = lev.load(str(scene)).trim(n=40, success_time=20.0, t_end=20.0)
    assert (api.advice, api.probability, api.widest_window_mass) == \
        (r["advice"], r["launch_odds"]["probability"], r["widest_window"]["mass"])
    # one answer type: the command's JSON is the API's answer's as_json(), key for key, but for the
    # command's own keys and the design's wall time
    from levitron.runtime.design.trim_answer import Trim
    assert type(api) is Trim and lev.Trim is Trim
    a = api.as_json()
    assert set(r) - set(a) == {"scene", "out", "provenance", "success"}
    assert r["success"] is api.success is True
    for d in (a, r):
        d["design"].pop("wall_s")
    # each in its face's words (runtime/words.py): the API's sentences name the Study method where
    # the command's name the command; every number and every other word is the same
    from levitron.runtime.words import _API_METHOD
    api_text = json.dumps(a, sort_keys=True)
    for command, method in _API_METHOD.items():
        api_text = api_text.replace(f"`{method}`", f"`levitron {command}`")
    assert api_text == json.dumps({k: r[k] for k in a}, sort_keys=True)
    assert "g" not in re.findall(r"[\d.] ?(\w+)", api.message)


def test_no_band_is_refused_in_one_line(tmp_path, capsys):
    """A dipole's potential b/z^2 has no maximum of Phi_2: no height where a spin holds a top."""
    scene = tmp_path / "dipole.toml"
    scene.write_text("\n".join(['name = "dipole"', "g = 1.0", 'units = "dimensionless"', "[top]",
                                "mass = 1.0", "A = 0.0044", "C = 0.00264", "moment = -1.0", "[plate]",
                                'kind = "expression"', 'phi0 = "b/z**2"', "[plate.params]", "b = 1.0",
                                "[model]", 'needs = ["reduced", "full", "linear"]']) + "\n")
    assert main(["trim", str(scene), *QUICK]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if "error" in line]   # (and a first derive's progress)
    assert len(err) == 1 and err[0].startswith("levitron trim: error: ") and "nothing to trim" in err[0], err


def test_the_mass_window_over_the_tops_mass_is_refused(capsys):
    """The band's masses do not depend on the top's mass (thesis 3.3.2: m(z) = -mu Phi_2(z)/g): a
    mass-window design over top.mass would return any mass; it is refused, pointing to trim."""
    assert main(["optimize", "thesis_stable", "--maximize", "mass-window", "--vary", "top.mass=0.05:0.052"]) == 2
    assert "levitron trim" in capsys.readouterr().err


def test_a_design_whose_launches_cannot_be_counted_still_answers(capsys):
    """At 28 degC thesis_air's 51.5 g top hovers over no hole of the box: the mass-window design
    stands, and its cost in launches is a warning saying why, not a failed command."""
    r = json.loads(_run(capsys, "optimize", "thesis_air", "--temperature", "28", "--maximize", "mass-window",
                        "--vary", "plate.hole=0.025:0.035", "--n", "10", "--quiet", "--json"))
    assert r["optimum"]["plate.hole"] > 0 and "launch_odds" not in r
    assert any(w.startswith("the launch odds are not computed: ") and "too heavy" in w for w in r["warnings"])


def test_a_corner_ipopt_cannot_climb_is_found_by_the_bounded_search(derived_model):
    """At 28 degC thesis_air's spin window is widest where sigma_lo(m) switches branch, a corner:
    IPOPT fails on spin-ratio over the band's masses, and the bounded search of the float route finds
    the corner, the same mass at which IPOPT's spin-range optimum lies (a second objective, a second
    method) to 1e-7, above every grid point."""
    model = derived_model("thesis_air", "temperature=28.0")
    box = [Vary("top.mass", 0.04908, 0.05115)]
    ratio = optimize(model, box, "spin-ratio", [], 20)
    assert ratio.solver_status.startswith("bounded search") and "corner" in ratio.warnings[0]
    assert ratio.verification["nlp"] is None and ratio.value >= ratio.verification["grid_best"]
    width = optimize(model, box, "spin-range", [], 20)
    assert width.solver_status.startswith("Solve")
    assert ratio.optimum["top.mass"] == pytest.approx(width.optimum["top.mass"], rel=1e-7)


def test_a_change_whose_odds_lie_inside_the_interval_as_written_is_no_change():
    """'add 0.018 g: 55.5 % -> 54.5 %' was advice inside its own noise: the best mass's odds inside
    the 95 % interval of the odds as written read "no change" (the best mass kept as data)."""
    from levitron.runtime.cli.commands.trim import human
    inside = trim_with((0.524, 0.586), 0.545)
    assert inside.no_change and inside.message.startswith("no change: the best mass (add 0.02 g")
    r = inside.as_json()
    assert r["no_change"] is True and r["advice"] == 0.05102
    assert human({**r, "out": None}).splitlines()[0].startswith("no change: the best mass (add 0.02 g")
    outside = trim_with((0.20, 0.26), 0.545)
    assert not outside.no_change and outside.message.startswith("add 0.02 g (to 51.02 g): launch odds")
    assert human({**outside.as_json(), "out": None}).startswith("add 0.02 g")


def test_a_change_the_paired_launches_decided_is_advised_even_inside_the_interval_as_written():
    """The mass as written, paired with the best on the fresh draws, stopped because McNemar's test
    decided their difference: the change is real even where the best's odds lie inside the start's
    interval (that interval also holds the best's own noise, which the pairing cancels), and is
    advised where the best floats more often; a decided difference the other way is no change."""
    better = trim_with((0.225, 0.294), 0.291, paired=True)
    assert not better.no_change
    assert better.message.startswith("add 0.02 g (to 51.02 g): launch odds 25.9 % (22.5-29.4 %) -> 29.1 %")
    assert "(as written on the first 250, paired: enough to decide the difference)" in better.message
    worse = trim_with((0.30, 0.36), 0.291, paired=True)
    assert worse.no_change and worse.message.startswith(
        "no change: the best mass (add 0.02 g (to 51.02 g)) floats 29.1 % (26.1-32.1 %), no more often than the "
        "mass as written, 33 % (30-36 %) on the answer's first 250 launches, paired")
