"""An expression plate's plate.z_range (scene/plates/expression.py, issue 26): the heights where its
formula holds. The equilibrium search and the bands stay inside it, a band cut by it says so, and
the range is a runtime search range, not part of the derivation (the input hash)."""
from __future__ import annotations

import json

import pytest

from levitron.scene.inputs import input_hash
import tomllib

from levitron.scene.load import validate
from levitron.runtime.cli.main import main

# the annulus's on-axis potential (thesis 2.3) as a formula, in units of its outer radius
ANNULUS = """name = "annulus_formula"
g = 1.0
units = "dimensionless"
[top]
mass = 1.03
A = 0.0044
C = 0.00264
moment = -1.0
[plate]
kind = "expression"
phi0 = "b*(z/sqrt(z**2 + R**2) - z/sqrt(z**2 + a**2))"
{range}
[plate.params]
b = 1.0
R = 1.0
a = 0.3
[model]
needs = ["reduced", "full", "linear"]
"""


def _equilibrium(tmp_path, capsys, text, name):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    assert main(["equilibrium", str(path), "--json", "--quiet"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert main(["equilibrium", str(path), "--quiet"]) == 0
    return r, capsys.readouterr().out


def test_a_range_cuts_the_band_and_says_so(tmp_path, capsys):
    """The whole formula's band is 0.146-0.315 (from z_c, where it opens: thesis 3.3.15); a range
    from 0.2 cuts it there, says so, and leaves its upper edge where it was."""
    whole, text = _equilibrium(tmp_path, capsys, ANNULUS.format(range=""), "whole")
    assert whole["stable_band"]["at_search_end"] == [False, False] and whole["z_range"] is None
    assert whole["stable_band"]["z"][0] == pytest.approx(whole["z_c"], rel=1e-9)
    assert "not a physical edge" not in text
    cut, text = _equilibrium(tmp_path, capsys, ANNULUS.format(range="z_range = [0.2, 2.0]"), "cut")
    assert cut["z_range"] == [0.2, 2.0] and cut["z_c"] is None
    assert cut["stable_band"]["z"][0] == 0.2 and cut["stable_band"]["at_search_end"] == [True, False]
    assert cut["stable_band"]["z"][1] == pytest.approx(whole["stable_band"]["z"][1], rel=1e-9)
    assert "its lower edge is the end of the formula's range, plate.z_range: not a physical edge" in text
    assert [e["z"] for e in cut["equilibria"]] == pytest.approx(
        [e["z"] for e in whole["equilibria"] if e["z"] >= 0.2], rel=1e-12)


def test_a_band_at_the_search_start_is_not_called_physics(tmp_path, capsys):
    """A cubic fit of a potential has a 'band' from the search's first height, 1e-4 of the length
    scale 1 (0.1 mm): said to be the search's end, with the key that states the formula's range."""
    cubic = "\n".join(['name = "cubic_fit"', "g = 9.81", "[top]", "mass = 0.02", "A = 2.2e-6", "C = 1.32e-6",
                       "moment = -0.65", "[plate]", 'kind = "expression"', 'phi0 = "a1*z + a2*z**2 + a3*z**3"',
                       "[plate.params]", "a1 = -0.01", "a2 = 0.5", "a3 = -4.0", "[model]",
                       'needs = ["reduced", "full", "linear"]']) + "\n"
    r, text = _equilibrium(tmp_path, capsys, cubic, "cubic")
    assert r["stable_band"]["z"][0] == pytest.approx(1e-4, rel=1e-12)
    assert r["stable_band"]["at_search_end"] == [True, False]
    assert "where the height search ends, not a physical edge" in text and "plate.z_range" in text


def test_the_range_is_not_derived():
    """Changing or adding z_range changes no generated code: one input hash."""
    hashes = {input_hash(validate(tomllib.loads(ANNULUS.format(range=r))).data)
              for r in ("", "z_range = [0.2, 2.0]", "z_range = [0.01, 0.5]")}
    assert len(hashes) == 1


@pytest.mark.parametrize("bad", ["[0.5, 0.2]", "[0.0, 1.0]", "0.2", '["a", 1.0]', "[0.1, 0.2, 0.3]"])
def test_a_bad_range_is_one_line(bad, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(ANNULUS.format(range=f"z_range = {bad}"))
    assert main(["equilibrium", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "plate.z_range" in err, err
