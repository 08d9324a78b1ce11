"""A launch says when its hand's spins include, or in air slow down through, an explosive
three-wave resonance inside the window (runtime/scan/launch_inputs.py resonance_warnings;
levitron_toy's at 213.1 rad/s, docs/resonances.md)."""
from __future__ import annotations

import json

from levitron.runtime.cli.main import main


def _warnings(capsys, *flags) -> list[str]:
    assert main(["launch", "levitron_toy", "--n", "4", "--t-end", "1", "--json", *flags]) == 0
    return json.loads(capsys.readouterr().out)["warnings"]


def test_a_hand_at_the_resonance_is_warned_and_one_far_from_it_is_not(capsys):
    at = [w for w in _warnings(capsys, "--spin", "normal:212,3") if "explosive resonance" in w]
    assert len(at) == 1 and "include the explosive resonance at 213.121 rad/s" in at[0]
    assert not [w for w in _warnings(capsys, "--spin", "normal:150,5") if "resonance" in w]


def test_a_top_slowing_down_through_it_in_air_is_warned(capsys):
    """Launched at 219-231 rad/s, the toy's spin (decay time 150 s) passes 213 rad/s within the
    success time of 75 s; a run of 1 s as success time does not reach it."""
    long = _warnings(capsys, "--spin", "normal:225,3", "--success-time", "75", "--t-end", "75")
    assert any("pass, slowing down over 75 s" in w for w in long)
    assert not [w for w in _warnings(capsys, "--spin", "normal:225,3") if "resonance" in w]


def test_a_design_says_the_launches_warning_at_its_optimum(capsys):
    """The launch-odds design (and so trim) carries the warnings of the launches it decides on."""
    assert main(["optimize", "levitron_toy", "--maximize", "launch-odds", "--vary", "top.mass=0.0209:0.0213",
                 "--spin", "normal:212,3", "--n", "8", "--t-end", "1", "--json"]) == 0
    w = json.loads(capsys.readouterr().out)["warnings"]
    # the launches' warning, worded as advice at the optimum (design_notes.with_resonance_advice)
    assert any("explosive resonance" in x and "launch below it" in x for x in w)
