"""`levitron optimize --maximize yield`: its flags refused where they mean nothing, and a small design
whose JSON and plain view say the yield with and without the washers (runtime/design/yield_design.py)."""
from __future__ import annotations

import json

import pytest

from levitron.runtime.cli.main import main


@pytest.mark.parametrize("argv, words", [
    (["--maximize", "spin-range", "--vary", "top.mass=0.05:0.052", "--washers", "0.0002"], "--maximize yield"),
    (["--maximize", "yield", "--vary", "top.mass=0.05:0.052", "--grid", "20"], "own grid"),
    (["--maximize", "yield", "--vary", "top.mass=0.05:0.052", "--washers", "0.2 g,heavy"], "not a mass"),
    (["--maximize", "yield", "--vary", "top.mass=0.05:0.052", "--kit", "spin=rel:1%"], "strength or mass"),
    (["--maximize", "yield", "--vary", "top.mass=0.05:0.052", "--kit", "plate.hole=normal:0.03,0.0001"],
     "deviation from the design"),
    (["--maximize", "yield", "--vary", "top.mass=0.05:0.052", "--kit", "plate.hole=abs:normal:0,0.01"],
     "the key's sign"),
])
def test_a_production_run_flag_out_of_place_is_refused_in_one_line(capsys, argv, words):
    assert main(["optimize", "thesis_air", *argv]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1


def test_a_yield_design_says_the_yield_with_the_washers_and_as_shipped(capsys, monkeypatch):
    """thesis_air, magnets +-2 %, washers of 0.4 and 0.8 g, 20 kits, a 3 s success time: the answer
    and the start are decided on the same fresh kits, every kit's washers are counted, and the plain
    view (the JSON's own words, yield_lines) names the yield, as shipped and what the owners put on."""
    from levitron.runtime.design.yield_answer import yield_lines
    from levitron.runtime.ui.human import Units
    from levitron.runtime.design import production
    monkeypatch.setattr(production, "CURVE_N", 30)      # the owner's curve on fewer launches: a quick test
    argv = ["optimize", "thesis_air", "--maximize", "yield", "--vary", "top.mass=0.0505:0.0520",
            "--washers", "0.4 g,0.8 g", "--kits", "20", "--success-time", "3", "--quiet"]
    assert main([*argv, "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["objective_name"] == "yield" and r["yield"]["kits"] == 20 and r["yield"]["seed"] == 1
    assert r["start_yield"]["seed"] == 1 and r["production"]["washers"] == pytest.approx([0.0004, 0.0008])
    assert sum(row["kits"] for row in r["washers_used"]) == 20
    assert r["search"]["evaluations"] <= 7 + 3            # the grid and the zoom, no point twice
    assert 0.0505 <= r["optimum"]["top.mass"] <= 0.0520
    import jsonschema
    from levitron.runtime.cli import schema
    jsonschema.Draft202012Validator(schema.schema("optimize")).validate(r)
    text = "\n".join(yield_lines(r, Units(si=True)))
    assert "yield (kits that float" in text and "as shipped, no washer" in text and " g: " in text


def test_a_yield_design_reads_the_production_table_and_spreads_a_scene_key(capsys, monkeypatch, tmp_path):
    """thesis_air with a [production] table (washers with a unit, 20 kits, the bore spread by 0.1 mm):
    the run takes the table as the flags would give it, each kit at its own bore, and its JSON
    validates against the schema."""
    from pathlib import Path

    import jsonschema
    from levitron.runtime.cli import schema
    from levitron.runtime.design import production, yield_design
    monkeypatch.setattr(production, "CURVE_N", 30)      # the owner's curve on fewer launches: a quick test
    monkeypatch.setitem(yield_design.GRID, 1, 3)        # and fewer points: the table and the JSON are the test
    scene = tmp_path / "made.toml"
    scene.write_text((Path(__file__).parents[2] / "scenes" / "thesis_air.toml").read_text(encoding="utf-8")
                     + '\n[production]\nwashers = ["0.4 g", "0.8 g"]\nkits = 20\n[production.kit]\n'
                     'plate.hole = "abs:normal:0,0.0001"\n', encoding="utf-8")
    argv = ["optimize", str(scene), "--maximize", "yield", "--vary", "top.mass=0.0505:0.0520",
            "--success-time", "3", "--quiet", "--json"]
    assert main(argv) == 0
    r = json.loads(capsys.readouterr().out)
    flags = production.Production.of({"plate.hole": "abs:normal:0,0.0001"}, [0.0004, 0.0008], 20)
    assert r["production"]["kit"] == dict(flags.specs) and r["production"]["kits"] == 20
    assert r["production"]["washers"] == pytest.approx([0.0004, 0.0008])
    assert sum(row["kits"] for row in r["washers_used"]) == 20 and r["yield"]["kits"] == 20
    assert r["owner_curve"]["position"][0] == pytest.approx(1 / 18)
    jsonschema.Draft202012Validator(schema.schema("optimize")).validate(r)
