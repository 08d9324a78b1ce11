"""Issue 19, "misleading answers": every summary says what it is (one test per item, each failing
on the code before its fix)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from runtime import cli

ROOT = Path(__file__).resolve().parent.parent


def plain(capsys, *argv) -> str:
    assert cli.main(list(argv)) == 0
    return capsys.readouterr().out


def as_json(capsys, *argv) -> dict:
    assert cli.main(list(argv) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


# ---- item 1: a reference value only beside the scene it describes

def test_thesis_reference_shown_for_the_thesis_scene(capsys):
    assert "vertically stable; thesis: 15.68 cm" in plain(capsys, "equilibrium", "thesis")
    assert as_json(capsys, "equilibrium", "thesis")["reference"]["z_stable"] == \
        {"value": 0.1568, "source": "thesis"}


@pytest.mark.parametrize("override", ["top.mass=0.0515", "plate.hole=0", "g=9.8"])
def test_thesis_reference_dropped_when_a_set_changes_the_scene(capsys, override):
    out = plain(capsys, "equilibrium", "thesis", "--set", override)
    assert "vertically stable" in out and "thesis:" not in out, out
    assert as_json(capsys, "equilibrium", "thesis", "--set", override)["reference"]["z_stable"] is None


def test_thesis_reference_dropped_for_a_copy_with_another_top(capsys, tmp_path):
    """The [reference] table travels with a copied file; its parameters are no longer the thesis's."""
    text = (ROOT / "scenes" / "thesis.toml").read_text()
    same, other = tmp_path / "mine.toml", tmp_path / "heavier.toml"
    same.write_text(text)
    other.write_text(text.replace("mass = 0.0284", "mass = 0.0515"))
    assert "thesis: 15.68 cm" in plain(capsys, "equilibrium", str(same))
    assert "thesis:" not in plain(capsys, "equilibrium", str(other))


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
