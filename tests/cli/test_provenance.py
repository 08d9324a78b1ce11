"""Reproducible output: every JSON object carries a provenance block (version, scene
path and hashes, overrides, command line, time); the report shows it, and its command, run again,
rebuilds the same numbers."""
from __future__ import annotations

import datetime
import html
import json
import re
import shlex

import pytest

from levitron.scene.load import load_scene
from levitron.runtime.cli import main as cli
from levitron.runtime.ui.provenance import version

KEYS = {"package", "version", "command", "time", "python", "scene", "scene_path", "overrides",
        "scene_hash", "input_hash"}
COMMANDS = {
    "info": ["info", "thesis"],
    "equilibrium": ["equilibrium", "thesis", "--set", "top.mass=0.0515"],
    "stability": ["stability", "thesis_stable", "--height", "0.105"],
    "field": ["field", "ring_magnet", "--at", "0.01,0,0.05"],
    "simulate": ["simulate", "thesis_stable", "--spin", "1000", "--tilt", "0.01", "--t-end", "0.05"],
    "scan": ["scan", "thesis_stable", "--spin", "500:1500:2", "--tilt", "0.01:0.02:2", "--t-end", "0.05"],
    "optimize": ["optimize", "thesis", "--fit-height", "0.0762"],
}


def run_json(capsys, argv) -> dict:
    assert cli.main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_json_object_has_provenance(name, capsys):
    argv = COMMANDS[name]
    prov = run_json(capsys, argv)["provenance"]
    assert set(prov) == KEYS
    assert prov["version"] == version() and prov["package"] == "levitron"
    assert shlex.split(prov["command"]) == ["levitron", *argv, "--json"]
    sets = [argv[i + 1] for i, a in enumerate(argv) if a == "--set"]
    scene = load_scene(argv[1], sets)
    assert prov["overrides"] == sets and prov["scene_path"] == str(scene.path.resolve())
    assert prov["scene_hash"] == scene.scene_hash()
    age = datetime.datetime.now(datetime.timezone.utc) - datetime.datetime.fromisoformat(prov["time"])
    assert datetime.timedelta(0) <= age < datetime.timedelta(minutes=10)


def test_the_scene_hash_tells_scenes_apart(capsys):
    a = run_json(capsys, ["info", "thesis"])["provenance"]
    b = run_json(capsys, ["info", "thesis", "--set", "top.mass=0.0515"])["provenance"]
    assert a["scene_hash"] != b["scene_hash"] and a["input_hash"] == b["input_hash"]   # numbers only


def test_input_hash_is_the_generated_models(capsys):
    prov = run_json(capsys, ["info", "thesis"])
    assert prov["provenance"]["input_hash"] == prov["input_hash"]


def test_a_command_of_several_scenes_has_provenance_too(capsys):
    prov = run_json(capsys, ["derive", "thesis"])["provenance"]
    assert prov["command"] == "levitron derive thesis --json" and "scene" not in prov


def test_the_report_shows_provenance_and_its_command_rebuilds_it(tmp_path, capsys):
    """The footer's command (with the --set the page was made with) gives the same numbers."""
    first = tmp_path / "a.html"
    facts = run_json(capsys, ["report", "thesis_stable", "--set", "top.mass=0.0512", "--out", str(first)])
    page = html.unescape(re.sub(r"<[^>]+>", "\n", first.read_text()))
    assert "Provenance" in page and facts["provenance"]["scene_hash"] in page
    # the provenance table's command, the page's last (the rebuild block above it names the saved
    # TOML instead: tests/runtime/report/test_teacher_page.py runs that one)
    command = next(ln for ln in reversed(page.splitlines()) if ln.startswith("levitron report "))
    assert "--set top.mass=0.0512" in command
    again = shlex.split(command)[1:]
    again[again.index("--out") + 1] = str(tmp_path / "b.html")
    rebuilt = run_json(capsys, again)
    for key in ("z_s", "spin_interval", "equilibria", "stable_band"):
        assert rebuilt[key] == facts[key], key
    assert rebuilt["provenance"]["scene_hash"] == facts["provenance"]["scene_hash"]
