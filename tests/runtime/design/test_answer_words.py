"""The launch and design answers own their words: each renders its plain view from its own fields
(`lines(units)`, one function beside the type, from its JSON), which the command line prints, its
`message` and repr reuse, the report places (the launch odds) and a notebook shows as a table in
the scene's display units. The answers here are built from their fields (no Monte Carlo, no model)."""
from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from levitron.scene.load import load_scene
from levitron.runtime.ui.human import Units
from tests.helpers.dimensionless import SCENE, si_units
from tests.helpers.trims import trim_with

SI, DL = Units(si=True), Units(si=False)


def _odds(p: float = 0.6, units: Units = SI):
    from levitron.runtime.scan.launch_answer import LaunchOdds
    details = {"probability": p, "probability_ci95": [p - 0.1, p + 0.1], "n": 40, "no_verdict": 0,
               "success_time": 10.0, "t_end": 10.0, "seed": 3, "integrator": "dop853", "tol": 1e-6,
               "flight_time": {"median": 7.5, "q1": 4.0, "q3": 10.0, "censored": 12,
                               "values": [2.0, 4.0, 7.5, 10.0, 10.0]},
               "ranking": [{"input": "tilt", "effect": 0.3, "noise": 0.1}],
               "outcomes": {"completed": 40}, "defaulted": ["tilt"],
               "inputs": {"spin": "normal:100,10", "tilt": "uniform:0,0.02", "offset": "normal:0,0.001"},
               "warnings": ["the launches reach ‹0.00651|m› off the axis"]}
    return LaunchOdds(p, (p - 0.1, p + 0.1), 40, 10.0, {"median": 7.5, "q1": 4.0, "q3": 10.0},
                      [("tilt", 0.3)], details, units, {}, "annulus", False)


@pytest.fixture(scope="module")
def annulus_scene(tmp_path_factory):
    path = tmp_path_factory.mktemp("words") / "unit_annulus.toml"
    path.write_text(SCENE)
    return load_scene(str(path))


def test_a_launch_answers_field_changes_its_plain_view_message_and_report_sentence_together():
    """One function words the odds (launch_answer.launch_lines): the command line's plain view, the
    API's message and the report's answer paragraph move with the answer's `probability`."""
    from levitron.runtime.cli.commands.launch import human
    from levitron.runtime.report.real_launch import odds_paragraph
    from levitron.runtime.words import render
    faces = []
    for p in (0.6, 0.25):
        odds = dataclasses.replace(_odds(), probability=p)
        cli = render(human(odds.as_json()), "cli", SI)
        report = render(odds_paragraph(odds, SI), "cli", SI)
        faces.append((cli, odds.message, report))
        head = f"{100 * p:.3g}% of 40 launches float at least 10 s"
        assert all(head in text for text in faces[-1]), faces[-1]
    assert all(a != b for a, b in zip(*faces))
    assert "60%" not in "".join(faces[1])
    # the same headline, word for word, in all three
    first = faces[1][0].splitlines()[0]
    assert faces[1][1].startswith(first) and first[1:] in faces[1][2]
    # the warning's quantity in display units, from its marker; the settings worded per face
    assert "6.51 mm off the axis" in faces[1][0] and "6.51 mm off the axis" in faces[1][1]
    assert "set them with --spin, --tilt" in faces[1][0] and "set them with spin, tilt" in faces[1][1]


def test_a_trims_field_changes_its_plain_view_and_message_together():
    from levitron.runtime.cli.commands.trim import human
    trim = trim_with((0.20, 0.26), 0.545)
    moved = dataclasses.replace(trim, mass=0.0500)
    for t in (trim, moved):
        first = human(t.as_json()).splitlines()[0]
        assert t.message.startswith(first) and repr(t) == f"Trim({first}; success=True)"
    assert human(trim.as_json()).splitlines()[0] != human(moved.as_json()).splitlines()[0]
    assert "add 1.02 g" in moved.message


def _answers(scene, units: Units) -> dict:
    """One answer of every launch and design type, in `units`, from made-up fields."""
    from levitron.runtime.design.compare import Comparison
    from levitron.runtime.design.design_answer import Design
    from levitron.runtime.design.fit_answer import Fit
    from levitron.runtime.design.fit_height import HeightFit
    from levitron.runtime.design.production import Production
    from levitron.runtime.design.yield_answer import YieldDesign
    from levitron.runtime.scan.scan_answer import Scan
    trim = trim_with((0.20, 0.26), 0.545)
    design = dataclasses.replace(trim.design, scene=scene, inputs={"offset": "normal:0,0.001"})
    block = {"probability": 0.5, "probability_ci95": [0.4, 0.6], "n": 100, "seed": 1, "successes": 50}
    shipped = {"yield": block, "as_shipped": block, "untrimmable": 0.1, "washers_used": {0.0: 50, 0.0004: 30},
               "curve": []}
    band = {"z": [0.1, 0.12], "mass": [0.05, 0.052]}
    return {
        "LaunchOdds": _odds(0.6, units),
        "Scan": Scan("tilt", np.array([100.0, 200.0]), np.array([0.01]), np.array([[True], [False]]),
                     np.array([[5.0], [2.0]]), [["completed"], ["completed"]],
                     [{"spin_interval": [90.0, 150.0], "z_s": 0.1}], 5.0, {}, 0.5, {"kind": "serial"}, 10, 0.5,
                     units=units, scene="annulus"),
        "Trim": dataclasses.replace(trim, design=design, units=units),
        "LaunchDesign": design,
        "Design": Design("spin-range", 2000.0, {"top.mass": 0.051}, {"top.mass": 0.0505}, 1900.0, 1950.0,
                         "Solve_Succeeded", 12, 0.11, 3.0, (500.0, 2500.0), band, [],
                         {"grid_points": 20, "grid_best": 1990.0}, scene),
        "Fit": Fit({"top.mass": {"value": 0.0515, "stderr": 1e-4, "at_bound": False}},
                   [{"quantity": "z_s", "value": 0.1, "model": 0.1001, "sigma": 1e-4, "normalized": 1.0}],
                   1.0, 0, 3, "converged", {"top.mass": 0.05}, units=units),
        "HeightFit": HeightFit(0.0762, "mu", -1.0, 0.0, False,
                               [{"z": 0.0762, "vertically_stable": False}, {"z": 0.157, "vertically_stable": True}],
                               {}, None, units),
        "YieldDesign": YieldDesign({"top.mass": 0.0512}, {"top.mass": 0.051}, shipped, shipped,
                                   Production.of(washers=[0.0004]), {}, 10.0, [], 0.5, 1.0, scene=scene),
        "Comparison": Comparison(
            [{"scene": "a", "z_s": 0.1, "band_z": [0.1, 0.12], "band_mass": [0.05, 0.052],
              "spin_interval": [500.0, 2500.0], "weight_window": [-0.001, 0.001], "launch_odds": block,
              "best_mass": 0.051, "best_launch_odds": block}],
            {"first_scene": "a", "source": {"spin": "given"}, "n": 100, "seed": 1, "success_time": 10.0,
             "inputs": {"offset": "normal:0,0.001"}}, units.si)}


def _table_text(html: str) -> str:
    """The text of an answer's table (its figure, an SVG, apart), tags out."""
    return re.sub(r"<[^>]+>", " ", html.split("</table>")[0])


def test_every_launch_and_design_answer_shows_a_table_in_the_scenes_display_units(annulus_scene):
    """`_repr_html_` of every type is a table of its plain view (a dimensionless scene's: no SI
    unit); the same answers of an SI scene show theirs (the check can fail); the repr and the
    message are the same lines."""
    answers = _answers(annulus_scene, DL)
    assert set(answers) == {"LaunchOdds", "Scan", "Trim", "LaunchDesign", "Design", "Fit", "HeightFit",
                            "YieldDesign", "Comparison"}
    for name, answer in answers.items():
        html = answer._repr_html_()
        text = _table_text(html)
        assert html.startswith("<div><table>") and "<tr>" in html, name
        assert si_units(text) == [] and si_units(repr(answer)) == [], (name, si_units(text), si_units(repr(answer)))
        first = " ".join(answer.lines()[0].split())
        assert repr(answer).startswith(f"{name}("), name
        if name == "Comparison":     # its message (the JSON's) is a line of its plain view, its repr
            assert answer.message in answer.lines() and answer.message in repr(answer)
        else:
            assert answer.message.startswith(answer.lines()[0].strip()) and first in repr(answer), name
        assert "‹" not in html + repr(answer) + answer.message and "«" not in html, name
    assert "<svg" in answers["Scan"]._repr_html_() and "<svg" in answers["LaunchOdds"]._repr_html_()
    si = _answers(load_scene("thesis_stable"), SI)
    assert all(si_units(_table_text(si[k]._repr_html_())) for k in ("LaunchOdds", "Scan", "Trim", "Design",
                                                                     "HeightFit", "Comparison"))


@pytest.mark.parametrize("key, start, to, words", [
    ("top.mass", 0.0515, 0.0519, "add 0.4 g"),
    ("top.mass", 0.0515, 0.0505, "take 1 g off"),
    ("top.mass", 0.0515, 0.0515, "keep the mass at 51.5 g"),
    ("plate.hole", 0.012, 0.0125, "set plate.hole from 0.012 to 0.0125"),
    ("plate.hole", 0.012, 0.012, "keep plate.hole at 0.012"),
])
def test_a_change_is_worded_and_no_change_is_a_keep(key, start, to, words):
    """A design that lands on the scene as written says keep, not "set KEY from A to A"."""
    from levitron.runtime.design.launch_design_answer import change_text
    assert change_text(key, start, to, SI) == words
