"""`levitron scenes` and `levitron keys [KIND]`: what a user of an installed wheel (no docs/, no
checkout) learns from the command line alone; and the scene-key docs writer writes only where asked."""
from __future__ import annotations

import json

import pytest
import tomllib

from levitron.scene.paths import SCENES_DIR
from levitron.scene.plates import KINDS, docs
from levitron.runtime.cli import main as cli


def _json(capsys, *argv) -> dict:
    assert cli.main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_scenes_lists_every_file_of_scenes(capsys):
    files = sorted(SCENES_DIR.glob("*.toml"))
    assert len(files) >= 5
    r = _json(capsys, "scenes")
    assert [s["name"] for s in r["scenes"]] == [p.stem for p in files]
    for row, path in zip(r["scenes"], files):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        assert row["plate"] == data["plate"]["kind"]
        assert row["units"] in ("SI", "dimensionless")
        assert row["description"] == data.get("description")
    assert r["success"] is True and "provenance" in r
    assert cli.main(["scenes"]) == 0
    out = capsys.readouterr().out.splitlines()
    for path in files:         # one line a scene: its name first, then its plate kind
        kind = tomllib.loads(path.read_text(encoding="utf-8"))["plate"]["kind"]
        assert any(ln.split()[:2] == [path.stem, kind] for ln in out), (path.stem, out)


def test_scenes_takes_no_scene(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["scenes", "thesis"])
    assert exc.value.code == 2
    assert "unrecognized arguments: thesis" in capsys.readouterr().err


def test_keys_of_annulus_with_units(capsys):
    r = _json(capsys, "keys", "annulus")
    rows = {k["name"]: k for k in r["keys"]}
    assert list(rows) == [k.name for k in KINDS["annulus"].keys]
    assert {k: v["unit"] for k, v in rows.items()} == {"radius": "m", "hole": "m", "murho": "J m",
                                                        "dipole_density": "A"}
    assert rows["radius"]["required"] and not rows["hole"]["required"] and rows["hole"]["default"] == "0"
    assert rows["murho"]["alternatives"] == ["dipole_density"]
    assert {c["name"] for c in r["plate_common"]} == {"temperature_coefficient", "tilt", "tilt_azimuth"}
    assert cli.main(["keys", "annulus"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith('[plate] kind = "annulus"')
    assert [ln.split()[:3] for ln in out[1:3]] == [["radius", "m", "required"], ["hole", "m", "default"]]


def test_keys_without_kind_lists_kinds_and_common_sections(capsys):
    r = _json(capsys, "keys")
    assert list(r["kinds"]) == list(KINDS)
    assert set(r["sections"]) == {"scene", "top", "field", "model", "reference", "launch", "production"}
    top = {k["name"]: k for k in r["sections"]["top"]}
    assert top["mass"] == {**top["mass"], "unit": "kg", "required": True}
    assert not top["moment"]["required"]      # murho in the plate stands in for it
    assert {k["name"] for k in r["sections"]["launch"]} >= {"spin", "tilt", "success_time", "n"}
    assert cli.main(["keys"]) == 0
    out = capsys.readouterr().out
    assert all(f"\n  {kind} " in out for kind in KINDS) and "[top]:" in out and "[launch]:" in out


def test_unknown_kind_is_one_line_listing_the_kinds(capsys):
    assert cli.main(["keys", "anulus"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert captured.out == "" and len(err.splitlines()) == 1
    assert err.startswith("levitron keys: error: unknown plate kind 'anulus'")
    assert all(kind in err for kind in KINDS) and "did you mean annulus?" in err


def test_docs_writer_writes_only_where_asked(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(docs, "DOC", tmp_path / "nowhere" / "scenes.md")   # a default it must not touch
    assert docs.main([]) == 0
    assert capsys.readouterr().out == docs.render()
    assert not docs.DOC.parent.exists()
    out = tmp_path / "scenes.md"
    assert docs.main(["--out", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == docs.render()
    assert docs.main(["--check", str(out)]) == 0
    out.write_text("stale", encoding="utf-8")
    assert docs.main(["--check", str(out)]) == 1
    assert "is stale" in capsys.readouterr().err
