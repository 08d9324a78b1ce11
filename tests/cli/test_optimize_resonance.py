"""A launch-odds design whose launches at the optimum cross an explosive resonance says on which
side of it to launch (runtime/design/design_notes.py with_resonance_advice, trim's
resonance_advice), in place of the launches' generic warning of it (levitron_toy's at 213 rad/s)."""
from __future__ import annotations

import json


from levitron.runtime.cli.main import main
from levitron.runtime.design.design_notes import with_resonance_advice
from levitron.runtime.design.launch_design_answer import LaunchDesign
from levitron.runtime.design.trim import resonance_advice
from levitron.runtime.scan.spreads import parse_dist


def _design(mass: float, spin: str, warnings: list[str]) -> LaunchDesign:
    odds = {"probability": 1.0, "probability_ci95": [0.7, 1.0], "n": 8, "seed": 1, "successes": 8}
    return LaunchDesign({"top.mass": mass}, {"top.mass": mass}, odds, odds, 1.0, [], {"spin": spin}, 1.0, 1.0,
                        0, 8, 0.0, warnings)


def test_the_advice_replaces_the_launches_warning_at_the_optimum(toy):
    m = toy.param("m")
    advice, generic = resonance_advice(toy, m, parse_dist("spin", "normal:212,3"), 1.0)
    got = with_resonance_advice(toy, _design(m, "normal:212,3", [generic, "top.mass is at a bound"]))
    assert got.warnings == [advice, "top.mass is at a bound"]
    assert "launch below it" in advice and "explosive resonance" in advice


def test_no_resonance_crossed_leaves_the_design_as_it_was(toy):
    design = _design(toy.param("m"), "normal:150,5", ["other"])
    assert with_resonance_advice(toy, design) is design


def test_the_command_says_which_side_to_launch_on(capsys):
    assert main(["optimize", "levitron_toy", "--maximize", "launch-odds", "--vary", "top.mass=0.0212:0.0216",
                 "--spin", "normal:212,3", "--n", "8", "--t-end", "1", "--workers", "1", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    said = [w for w in r["warnings"] if "explosive resonance" in w]
    assert len(said) == 1 and "launch below it" in said[0], r["warnings"]
    assert said[0].startswith(f"at {r['optimum']['top.mass']:.6g} kg the hand's spins cross"), said[0]
