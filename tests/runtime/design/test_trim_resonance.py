"""Where the hand's spins cross an explosive resonance (docs/resonances.md; levitron_toy's at
213.121 rad/s, square's at 314.361 rad/s), trim says once, of the mass the person sets, on which
side of it to launch (runtime/design/trim.py resonance_advice, gated by the launch's own
runtime/scan/launch_inputs.py resonance_warnings)."""
from __future__ import annotations

import json

import pytest

import levitron as lev
from levitron.runtime.cli.main import main
from levitron.runtime.design.trim import resonance_advice
from levitron.runtime.scan.spreads import parse_dist
from levitron.runtime.words import render


def _advice(model, spin: str, success_time: float = 1.0) -> str | None:
    said = resonance_advice(model, model.param("m"), parse_dist("spin", spin), success_time)
    return None if said is None else render(said[0], "cli")


def test_a_hand_at_the_resonance_is_told_to_launch_below_it(toy):
    text = _advice(toy, "normal:212,3")
    assert "explosive resonance at 213.121 rad/s" in text and "launch below it" in text, text
    assert "207.121 rad/s or less" in text and "slows down" not in text, text     # 2 sd clear of it


def test_in_air_a_hand_above_it_is_told_below_it_too(toy):
    """Launched at 219-231 rad/s, the toy's spin (decay time 150 s) slows through 213 rad/s in 75 s."""
    text = _advice(toy, "normal:225,3", 75.0)
    assert "launch below it" in text and "slows down through it in flight" in text, text


def test_in_vacuum_a_hand_above_it_is_told_above_it():
    square = lev.load("square").model               # no air: the side of the hand's mean
    text = _advice(square, "normal:318,3")
    assert "resonance at 314.361 rad/s" in text and "launch above it" in text and "320.361" in text, text


@pytest.mark.parametrize("spin, success_time", [("normal:150,5", 75.0), ("normal:225,3", 1.0)])
def test_no_advice_where_no_resonance_is_crossed(toy, spin, success_time):
    assert _advice(toy, spin, success_time) is None


def test_trim_says_it_once_of_the_mass_it_advises(capsys):
    assert main(["trim", "levitron_toy", "--spin", "normal:212,3", "--n", "8", "--t-end", "1", "--workers", "1",
                 "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    said = [w for w in r["warnings"] if "explosive resonance" in w]
    sets = r["mass"] if r["no_change"] else r["advice"]
    assert len(said) == 1 and "launch below it" in said[0], r["warnings"]
    assert said[0].startswith(f"at {sets:.6g} kg the hand's spins cross"), said[0]
