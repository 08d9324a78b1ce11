"""Every `--json` answer carries `success`, the Python API answer's `success` (runtime/cli/success.py)."""
from __future__ import annotations

import json

import pytest

import levitron as lev
from levitron.results import LaunchOdds
from levitron.runtime.cli import main as cli
from levitron.runtime.cli.success import success


def _json(capsys, argv) -> dict:
    assert cli.main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("scene, method, command", [
    ("thesis", "equilibria", "equilibrium"),        # a vertically stable height: True
    ("thesis", "stability", "stability"),           # above the band, no stable spin: False
    ("thesis_stable", "stability", "stability"),    # 460-2740 rad/s: True
])
def test_success_is_the_api_answers(capsys, scene, method, command):
    r = _json(capsys, [command, scene])
    api = getattr(lev.load(scene), method)()
    assert r["success"] is api.success
    assert list(r)[-2:] == ["provenance", "success"]      # the one key added, after the others


def test_both_values_occur(capsys):
    assert _json(capsys, ["stability", "thesis"])["success"] is False
    assert _json(capsys, ["equilibrium", "thesis"])["success"] is True
    assert _json(capsys, ["keys", "loop"])["success"] is True


def test_plain_view_unchanged(capsys):
    assert cli.main(["scenes"]) == 0
    assert "success" not in capsys.readouterr().out


@pytest.mark.parametrize("outcomes", [{"completed": 3}, {"completed": 2, "left_box": 1, "cannot_hover": 1},
                                      {"completed": 2, "step_budget": 1}, {}])
def test_launch_rule_is_launch_odds(outcomes):
    details = {"outcomes": outcomes}
    odds = LaunchOdds(0.5, (0.1, 0.9), 4, 1.0, {}, [], details)
    assert success("launch", details) is odds.success


def test_rules_read_the_answer():
    assert success("simulate", {"status": "completed"}) and success("simulate", {"status": "left_box"})
    assert not success("simulate", {"status": "step_budget"})
    assert success("scan", {"status": [["completed", "left_box"], ["no_hover_height", "completed"]]})
    assert not success("scan", {"status": [["completed", "step_budget"]]})
    assert success("trim", {"launch_odds": {"probability": 0.2}})
    assert not success("trim", {"launch_odds": {"probability": 0}})
    assert success("optimize", {"success": False}) is False          # a fit that states its own
    assert success("info", {}) is True
