"""A design point where the top cannot hover is an answer, not an error: `launch` and
`Study.launch` give probability 0 with the reason (exit 0), as the launch-odds design counts it."""
from __future__ import annotations

import json

import levitron as lev
from levitron.runtime.cli.main import main
from levitron.runtime.design.launch_design import odds_at
from levitron.runtime.scan import launch_odds as mc

HEAVY = "top.mass=0.06"      # thesis_air's plate holds at most 52.5 g


def test_launch_of_a_top_too_heavy_to_hover_answers_zero_with_the_reason(capsys):
    assert main(["launch", "thesis_air", "--set", HEAVY, "--n", "30", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["probability"] == 0.0 and r["probability_ci95"] == [0.0, 0.0] and r["n"] == 30
    assert r["outcomes"] == {"cannot_hover": 30} and "too heavy" in r["reason"]
    assert main(["launch", "thesis_air", "--set", HEAVY, "--n", "30"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("launch odds: 0% of 30 launches float: the top cannot hover")


def test_the_api_and_the_design_count_it_the_same_way(derived_model):
    odds = lev.load("thesis_air", overrides={"top.mass": 0.06}).launch(n=12)
    assert odds.probability == 0.0 and odds.reason and odds.success
    assert odds.message.startswith("launch odds: 0% of 12 launches float: the top cannot hover")
    model = derived_model("thesis_air")
    scored = odds_at(model.ref, ["top.mass"], [0.06], mc.Request({}, n=12))
    assert scored["probability"] == odds.probability == 0.0
