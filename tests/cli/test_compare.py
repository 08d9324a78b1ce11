"""`levitron compare`: every scene launched by one hand (runtime/design/compare.py): each row's odds
are exactly what `levitron launch SCENE` gives with that hand as flags (same seed, same draws)."""
from __future__ import annotations

import json

import pytest

from levitron.runtime.cli import main as cli

from tests.helpers.dimensionless import SCENE

HAND = ["--spin", "normal:1500,150", "--tilt", "uniform:0,0.02", "--tilt-azimuth", "uniform:0,6.283185307179586",
        "--offset", "normal:0,0.001", "--velocity", "normal:0,0.01", "--mass", "rel:normal:0,0.002",
        "--strength", "rel:normal:0,0.005", "--n", "16", "--success-time", "2", "--t-end", "2", "--workers", "1"]
SCENES = ["thesis_air", "levitron_toy", "thesis_stable"]


def _json(argv, capsys) -> dict:
    assert cli.main(argv) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def compared():
    import contextlib
    import io
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert cli.main(["compare", *SCENES, *HAND, "--json"]) == 0
    return json.loads(out.getvalue())


def test_each_row_is_the_scenes_own_launch_under_the_same_flags(compared, capsys):
    assert [r["scene"] for r in compared["rows"]] == SCENES
    assert compared["hand"]["source"]["spin"] == "given"
    for row in compared["rows"]:
        alone = _json(["launch", row["scene"], *HAND, "--json"], capsys)
        assert row["launch_odds"]["probability"] == alone["probability"]
        assert row["launch_odds"]["successes"] == alone["successes"]
    air, toy, stable = compared["rows"]
    assert air["launch_odds"]["probability"] > 0          # 1500 rad/s: in the thesis top's window
    assert toy["launch_odds"]["probability"] == 0         # ... far above the toy's (98-241 rad/s)
    assert air["band_mass"][0] < air["mass"] < air["band_mass"][1]
    assert air["weight_window"] == pytest.approx([air["band_mass"][0] - air["mass"],
                                                  air["band_mass"][1] - air["mass"]])
    assert air["best_mass"] is not None and 0 <= air["best_launch_odds"]["probability"] <= 1


def test_without_flags_the_first_scenes_hand_is_everyones(capsys):
    argv = ["--n", "16", "--t-end", "2", "--workers", "1"]
    r = _json(["compare", "thesis_stable", "thesis_air", *argv, "--json"], capsys)
    first = _json(["launch", "thesis_stable", *argv, "--json"], capsys)
    assert r["rows"][0]["launch_odds"]["probability"] == first["probability"]
    assert r["hand"]["first_scene"] == "thesis_stable"
    assert set(r["hand"]["source"].values()) == {"thesis_stable"}
    spin = r["hand"]["inputs"]["spin"]            # the first scene's default spin, for both
    from levitron.runtime.cli.commands import compare
    text = compare.human(r)                       # the plain view of the same answer
    assert text.startswith("one hand for every scene: the launch spread of thesis_stable")
    assert "hovers at" in text and "thesis_air" in text and spin.split(":")[1].split(",")[0][:4] in text


def test_a_dimensionless_scene_is_not_compared_with_si_ones(tmp_path, capsys):
    path = tmp_path / "unit_annulus.toml"
    path.write_text(SCENE)
    assert cli.main(["compare", "thesis_stable", str(path), "--n", "16"]) == 2
    err = capsys.readouterr().err
    assert "dimensionless" in err and len(err.strip().splitlines()) == 1


def test_the_first_scenes_production_table_is_everyones_under_the_flags(tmp_path, capsys):
    """As the hand: the production run of every scene's yield is the first scene's [production]
    table (its washers here), with the flags over it (--kits)."""
    from pathlib import Path

    import levitron
    shipped = Path(levitron.__file__).parent / "scenes" / "thesis_air.toml"
    path = tmp_path / "air_kits.toml"
    path.write_text(shipped.read_text() + '\n[production]\nwashers = ["0.2 g", "0.4 g"]\nkits = 300\n')
    argv = ["--n", "8", "--t-end", "1", "--success-time", "1", "--workers", "1", "--kits", "10"]
    r = _json(["compare", str(path), "thesis_stable", *argv, "--json"], capsys)
    prod = r["hand"]["production"]
    assert prod["washers"] == pytest.approx([0.0002, 0.0004]) and prod["kits"] == 10
