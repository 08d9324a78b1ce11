"""No misleading answers: every summary says what it is (one test per item, each failing
on the code before its fix)."""
from __future__ import annotations

import re

import json
from pathlib import Path

import pytest

from levitron.runtime.cli import main as cli

ROOT = Path(__file__).resolve().parents[2]


def plain(capsys, *argv) -> str:
    assert cli.main(list(argv)) == 0
    return capsys.readouterr().out


def as_json(capsys, *argv) -> dict:
    assert cli.main(list(argv) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


# ---- item 1: a reference value only beside the scene it describes

def test_thesis_reference_shown_for_the_thesis_scene(capsys):
    out = plain(capsys, "equilibrium", "thesis")
    assert "vertically stable; thesis: 15.68 cm" in out and "unmodified" not in out
    assert as_json(capsys, "equilibrium", "thesis")["reference"]["z_stable"] == \
        {"value": 0.1568, "uncertainty": None, "source": "thesis", "describes": True}


@pytest.mark.parametrize("override", ["top.mass=0.0515", "plate.hole=0", "g=9.8", "temperature=28.0"])
def test_thesis_reference_marked_when_a_set_changes_the_scene(capsys, override):
    """Issue 28: under --set (or --temperature) the stated value stays, marked as for the
    unmodified scene (it used to vanish silently; before that it stood beside another top's height)."""
    out = plain(capsys, "equilibrium", "thesis", "--set", override)
    assert "thesis: 15.68 cm (reference is for the unmodified scene)" in out, out
    ref = as_json(capsys, "equilibrium", "thesis", "--set", override)["reference"]["z_stable"]
    assert ref["value"] == 0.1568 and ref["describes"] is False


def test_thesis_reference_marked_for_a_copy_with_another_top(capsys, tmp_path):
    """The [reference] table travels with a copied file; its parameters are no longer the thesis's."""
    text = (ROOT / "scenes" / "thesis.toml").read_text()
    same, other = tmp_path / "mine.toml", tmp_path / "heavier.toml"
    same.write_text(text)
    other.write_text(text.replace("mass = 0.0284", "mass = 0.0515"))
    mine = plain(capsys, "equilibrium", str(same))
    assert "thesis: 15.68 cm" in mine and "unmodified" not in mine
    assert "thesis: 15.68 cm (reference is for the unmodified scene)" in plain(capsys, "equilibrium", str(other))


# ---- item 2: `stability --height Z` is for the top that hovers at Z

def test_stability_at_a_height_is_for_the_top_that_hovers_there(capsys):
    """The 51.5 g top hovers at 10.65 cm; the top that hovers at 10.5 cm weighs m(z) = -mu Phi_2/g
    = 51.85 g. Its interval must equal the one of the scene with that mass, found at its own
    equilibrium (an independent path: the equilibrium finder, not --height)."""
    at = as_json(capsys, "stability", "thesis_stable", "--height", "0.105")
    assert at["mass"] == pytest.approx(0.05185, abs=5e-6) and at["scene_mass"] == 0.0515
    own = as_json(capsys, "stability", "thesis_stable", "--set", f"top.mass={at['mass']!r}")
    assert own["z_s"] == pytest.approx(0.105, rel=1e-9)
    assert at["spin_interval"] == pytest.approx(own["spin_interval"], rel=1e-8)
    assert at["spin_interval"][1] == pytest.approx(2685, abs=1)        # not the 51.5 g top's 2676
    out = plain(capsys, "stability", "thesis_stable", "--height", "0.105")
    assert "463.7-2685 rad/s" in out
    assert "for the top that hovers there, of mass 51.85 g (the scene's top is 51.5 g)" in out
    assert "for the 51.5 g top" not in out


def test_stability_at_a_height_where_no_top_hovers_is_refused(capsys):
    assert cli.main(["stability", "thesis_stable", "--height", "0.01"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no top hovers at z = 0.01 m" in err


# ---- item 7: the thesis approximations never read like an answer

def test_no_interval_no_approximations(capsys):
    out = plain(capsys, "stability", "thesis")
    assert out.startswith("spin_interval: none")
    assert "rad/s" not in out and "approximation" not in out, out
    assert as_json(capsys, "stability", "thesis")["approximations"]["sigma1"] is not None   # JSON keeps them


def test_approximations_labelled_as_another_tops(capsys):
    out = plain(capsys, "stability", "thesis_stable")
    line = next(ln for ln in out.splitlines() if "3.3.22" in ln)
    assert line.startswith("for comparison, not this top's interval: ")
    assert "for the 52.49 g top at z_c = 9.948 cm: 479.2-2516 rad/s" in line


# ---- item 4: optima and fits on a bound, and poor fits, say so (plain view, JSON, API)

def test_design_optimum_at_a_bound_says_so(capsys):
    """spin-range falls with the mass above 50.93 g: the box 51-52 g stops the optimum at 51 g."""
    argv = ["optimize", "thesis_stable", "--maximize", "spin-range", "--vary", "top.mass=0.0510:0.0520"]
    r = as_json(capsys, *argv)
    assert r["optimum"]["top.mass"] == pytest.approx(0.051, rel=1e-9)
    assert r["at_bound"] == {"top.mass": "lower"}
    assert any("at the bound: widen --vary" in w for w in r["warnings"])
    assert "at the bound: widen --vary" in r["message"]
    out = plain(capsys, *argv)
    assert "warning: top.mass = 0.051 is at the lower bound of --vary" in out
    import levitron as lev
    res = lev.load("thesis_stable").optimize("spin-range", {"top.mass": (0.0510, 0.0520)})
    assert res.at_bound == {"top.mass": "lower"} and res.success and "widen vary" in res.message   # the API's words


def test_design_interior_optimum_has_no_warning(capsys):
    r = as_json(capsys, "optimize", "thesis_stable", "--maximize", "spin-range", "--vary",
                "top.mass=0.0505:0.0524")
    assert r["at_bound"] == {} and r["warnings"] == []


def test_fit_at_a_bound_and_poor_says_so(capsys, tmp_path):
    """One height (10.30 cm +- 0.1 mm) that no mass in the box reproduces: the fit stops at the
    upper bound with chi2 ~ 500 on 0 degrees of freedom; it converged, and it is poor."""
    data = tmp_path / "h.csv"
    data.write_text("quantity,value,sigma\nz_s,0.1030,0.0001\n")
    argv = ["optimize", "thesis_stable", "--fit", str(data), "--vary", "top.mass=0.0510:0.0518"]
    r = as_json(capsys, *argv)
    assert r["parameters"]["top.mass"]["at_bound"] and r["solver_status"] == "converged"
    assert any("at the bound: widen --vary" in w for w in r["warnings"])
    assert any(w.startswith("the fit is poor: chi2 = ") for w in r["warnings"])
    out = plain(capsys, *argv)
    assert "warning: the fit is poor" in out and "warning: top.mass = 0.0518 is at the upper bound" in out


def test_poor_fit_with_degrees_of_freedom(capsys, tmp_path):
    """Three heights of three masses that the plate's strength cannot all reproduce: chi2/dof ~ 110."""
    data = tmp_path / "h.csv"
    data.write_text("quantity,value,sigma,overrides\nz_s,0.1060,0.0001,top.mass=0.0515\n"
                    "z_s,0.1050,0.0001,top.mass=0.0516\nz_s,0.1030,0.0001,top.mass=0.0517\n")
    r = as_json(capsys, "optimize", "thesis_stable", "--fit", str(data), "--vary",
                "plate.murho=-0.0028:-0.0025")
    assert r["dof"] == 2 and r["objective"] / 2 > 100
    assert [w for w in r["warnings"] if w.startswith("the fit is poor: chi2/dof = ")]


def test_good_fit_has_no_warning(capsys, tmp_path):
    """The scene's own height, measured to 0.1 mm: reproduced exactly, no warning."""
    z = as_json(capsys, "stability", "thesis_stable")["z_s"]
    data = tmp_path / "h.csv"
    data.write_text(f"quantity,value,sigma\nz_s,{z!r},0.0001\n")
    r = as_json(capsys, "optimize", "thesis_stable", "--fit", str(data), "--vary", "top.mass=0.0510:0.0520")
    assert r["warnings"] == [] and r["parameters"]["top.mass"]["value"] == pytest.approx(0.0515, rel=1e-7)


# ---- item 6: spin-range over the mass needs no stiffness constraint

def test_unconstrained_spin_range_is_solved(capsys):
    """Refused before ("needs --constrain stiffness>=K ... grows without bound"); sigma_hi stays
    finite at z_c on thesis_stable, and the optimum is the constrained one's (the README's
    0.0509296 with stiffness>=0.5, a constraint that is not active there)."""
    r = as_json(capsys, "optimize", "thesis_stable", "--maximize", "spin-range", "--vary",
                "top.mass=0.0505:0.0524")
    assert r["optimum"]["top.mass"] == pytest.approx(0.0509296, rel=1e-6)
    assert r["stiffness"] > 0.5 and r["spin_interval"][1] == pytest.approx(2841, abs=1)


def test_optimum_at_vanishing_stiffness_is_reported_with_a_warning(capsys):
    """A box 2e-6 to 4e-6 (relative) below the largest mass that hovers (52.492 g): the top hovers
    just above z_c, the stiffness is 0.7% of m g / z_s, the interval stays bounded (478.7-2533)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.cli.commands.common import load
    from levitron.runtime.model.load import load_model
    top = eqm.equilibria_of(load_model(load("thesis_stable"))).max_mass
    box = f"top.mass={top * (1 - 4e-6)!r}:{top * (1 - 2e-6)!r}"
    r = as_json(capsys, "optimize", "thesis_stable", "--maximize", "spin-range", "--vary", box)
    assert 0 < r["stiffness"] < 0.05 and r["spin_interval"][1] < 2600
    assert any(w.startswith("the optimum sits at vanishing stiffness: k = ") for w in r["warnings"])


def test_unbounded_edge_is_refused_and_says_where(thesis_model, monkeypatch):
    """check_bounded on the float route at z_c of thesis_stable: the interval from 478.9 rad/s is
    bounded there (no refusal), the one opened by the diverging root of the ray cubic (beyond 1e23
    rad/s) is not, and is refused naming the point and z_c. At the float z_c itself Phi_3 is
    rounding (+-1e-14, its sign set by the last bits of the generated onaxis), and the diverging
    root exists only where Phi_3 > 0: so z_c is taken one part in 1e14 below the float root, where
    Phi_3 = +4.7e-13 whatever the rounding."""
    import dataclasses

    from levitron.scene.load import load_scene
    from levitron.runtime.design import edge as design_edge
    from levitron.runtime.errors import UserError
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene("thesis_stable"))
    found = design_edge.eqm.equilibria_of

    def below_z_c(model, p=None, bands=False):
        rep = found(model, p, bands)
        return dataclasses.replace(rep, z_c=rep.z_c * (1 - 1e-14))
    monkeypatch.setattr(design_edge.eqm, "equilibria_of", below_z_c)
    assert model.onaxis(below_z_c(model, model.p).z_c)[3] > 1e-13
    design_edge.check_bounded(model, model.p, (478.0, 2533.0), "top.mass = 0.052492")
    with pytest.raises(UserError) as exc:
        design_edge.check_bounded(model, model.p, (1e26, 2e26), "top.mass = 0.052492")
    assert re.search(r"unbounded at top.mass = 0.052492: .* z_c = 0.0994772 m", exc.value.words("cli")), exc.value


# ---- item 5: scan summaries show the runs as they are; "cannot hover" is not "fell"

def _scan_result(levitating, status=None, axis="tilt"):
    """A scan's JSON as the command makes it (runtime/scan/scan_answer.py Scan.as_json), 4 spins x 1 row."""
    spins = [9.5, 10.5, 11.5, 12.5]
    return {"axes": ["spin", axis], "grid": {"spin": spins, axis: [0.01]},
            "levitating": [[v] for v in levitating],
            "status": [[s] for s in (status or ["" for _ in spins])],
            "fraction_levitating": sum(levitating) / 4, "points": 4, "t_end": 2.0,
            "spin_interval": None, "wall_s": 0.1, "runner": {"kind": "serial"}, "out": None}


def test_scan_row_with_a_gap_prints_both_runs():
    """A column inside the range fell: the row reads two runs, never 9.5-12.5."""
    from levitron.runtime.cli.commands.scan import human
    from levitron.runtime.ui.human import Units
    row = human(_scan_result([True, False, True, True])).splitlines()[1]
    u = Units(si=True)
    assert f"stays up for spin {u.rate(9.5)} and {u.rate_span(11.5, 12.5)} (3 of 4)" in row, row
    assert "9.5-12.5" not in row


def test_scan_row_with_one_stable_spin_is_no_range():
    from levitron.runtime.cli.commands.scan import human
    row = human(_scan_result([False, True, False, False])).splitlines()[1]
    assert "10.5-10.5" not in row and "stays up for spin 10.5 rad/s (" in row, row


def test_scan_masses_that_cannot_hover_are_not_falls(capsys, tmp_path, legend_texts):
    """53 and 54 g exceed the largest mass the thesis plate holds (52.49 g): no run is made (the
    JSON says no_hover_height); the text says "cannot hover" and the map draws them grey, apart
    from the colour map's 'fell at once'."""
    legends = legend_texts
    argv = ["scan", "thesis_stable", "--spin", "300:3000:6", "--mass", "0.050:0.054:5", "--t-end", "0.5",
            "--out", str(tmp_path / "m.png")]
    out = plain(capsys, *argv)
    assert "mass 53 g: cannot hover (no equilibrium: not simulated)" in out
    assert "mass 54 g: cannot hover" in out
    assert "mass 53 g: falls" not in out and "mass 52 g: stays up" in out
    assert "cannot hover (no equilibrium: not simulated)" in legends
    r = as_json(capsys, *argv[:-2])
    assert all(st == "no_hover_height" for row in r["status"] for st in row[3:])


# ---- found beside the list: `stability --height` below z_c crashed on an unbounded interval

def test_stability_at_a_vertically_unstable_height_says_so(capsys):
    """9.5 cm is below z_c (9.948 cm): the top that hovers there (51.95 g) is vertically unstable.
    The view crashed (TypeError) formatting the route's unbounded intervals as 'further intervals'."""
    out = plain(capsys, "stability", "thesis_stable", "--height", "0.095")
    assert out.startswith("spin_interval: none")
    assert "reason: z_s = 9.5 cm is not vertically stable" in out and "further intervals" not in out


def test_an_unbounded_interval_reads_above():
    from levitron.runtime.physics.stability.view import interval
    from levitron.runtime.ui.human import Units
    assert interval([1.2e26, None], Units(si=True)).startswith("above 1.2e26 rad/s")
