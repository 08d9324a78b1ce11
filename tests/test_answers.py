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
