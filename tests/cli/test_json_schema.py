"""Every command's --json answer validates against its JSON Schema (runtime/cli/schema.py, built from the
answer types and runtime/cli/schema_keys.py), the schemas are valid draft 2020-12 with closed top levels,
docs/schemas/ holds exactly what the generator writes, and an undeclared key fails."""
from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.cli import schema

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ["--n", "8", "--t-end", "2", "--workers", "1"]


def _json(capsys, argv) -> dict:
    assert cli.main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _check(capsys, argv) -> dict:
    out = _json(capsys, argv)
    errors = [f"{list(e.absolute_path)}: {e.message[:300]}" for e in _validator(argv[0]).iter_errors(out)]
    assert not errors, f"levitron {' '.join(argv)} --json: " + "; ".join(errors)
    return out


_VALIDATORS: dict = {}


def _validator(command: str):
    if command not in _VALIDATORS:
        _VALIDATORS[command] = jsonschema.Draft202012Validator(schema.schema(command))
    return _VALIDATORS[command]


def test_every_command_has_a_valid_closed_schema():
    assert set(schema.commands()) == set(cli.COMMANDS)
    for command in schema.commands():
        s = schema.schema(command)
        jsonschema.Draft202012Validator.check_schema(s)
        assert s["$schema"] == schema.DRAFT
        for shape in s.get("anyOf", [s]):
            assert {"provenance", "success"} <= set(shape["required"]), command
            assert shape["additionalProperties"] is False or shape.get("title", "").startswith("another kind")


def test_committed_schemas_are_the_generated_ones(tmp_path):
    """docs/schemas/ is `python -m levitron.runtime.cli.schema`'s output (run it after changing a key)."""
    written = schema.write_all(tmp_path)
    committed = ROOT / "docs" / "schemas"
    assert sorted(p.name for p in committed.glob("*.json")) == sorted(p.name for p in written)
    for path in written:
        assert (committed / path.name).read_text(encoding="utf-8") == path.read_text(encoding="utf-8"), \
            f"docs/schemas/{path.name} is stale: run python -m levitron.runtime.cli.schema"


def test_cheap_answers_validate(capsys):
    for argv in (["scenes"], ["keys"], ["keys", "annulus"], ["info", "thesis"],
                 ["field", "ring_magnet", "--at", "0.01,0,0.05"], ["field", "thesis", "--at", "0,0,0.1"],
                 ["schema"], ["schema", "stability"]):
        _check(capsys, argv)


def test_equilibrium_and_stability_validate(capsys):
    for argv in (["equilibrium", "thesis"], ["stability", "thesis"], ["stability", "thesis_stable", "--spin", "1000"]):
        _check(capsys, argv)


@pytest.mark.parametrize("argv", [
    ["simulate", "thesis_stable", "--spin", "1000", "--t-end", "0.5"],
    ["simulate", "thesis", "--spin", "1000", "--t-end", "0.5"],          # falls: no interval
    ["scan", "thesis_stable", "--spin", "500:1000:2", "--tilt", "0.01:0.01:1", "--t-end", "0.2", "--workers", "1"],
    ["launch", "thesis_air", *LAUNCH],
    ["optimize", "thesis", "--fit-height", "0.105"],
], ids=["simulate", "simulate-falls", "scan", "launch", "optimize-fit-height"])
def test_runs_validate(capsys, argv):
    _check(capsys, argv)


@pytest.mark.parametrize("argv", [
    ["optimize", "thesis_stable", "--maximize", "spin-range", "--vary", "top.mass=0.0505:0.0524", "--grid", "20"],
    ["optimize", "thesis_air", "--maximize", "launch-odds", "--vary", "top.mass=0.0505:0.0524", *LAUNCH],
    ["trim", "thesis_air", *LAUNCH],
    ["compare", "thesis_air", "levitron_toy", *LAUNCH],
    ["bench", "thesis_stable", "--quick"],
], ids=["optimize-design", "optimize-launch-odds", "trim", "compare", "bench"])
def test_expensive_runs_validate(capsys, argv, tmp_path):
    if argv[0] == "bench":
        argv = [*argv, "--out", str(tmp_path)]
    _check(capsys, argv)


def test_files_validate(capsys, tmp_path):
    """figures and report write files: into a temporary folder."""
    _check(capsys, ["figures", "thesis", "--quick", "--out", str(tmp_path / "figures")])
    _check(capsys, ["report", "thesis", "--out", str(tmp_path / "thesis.html")])


def test_an_undeclared_or_missing_key_fails(capsys):
    out = _json(capsys, ["equilibrium", "thesis"])
    validator = _validator("equilibrium")
    validator.validate(out)
    with pytest.raises(jsonschema.ValidationError, match="surprise"):
        validator.validate({**out, "surprise": 1})
    with pytest.raises(jsonschema.ValidationError, match="z_c"):
        validator.validate({k: v for k, v in out.items() if k != "z_c"})
    with pytest.raises(jsonschema.ValidationError):
        validator.validate({**out, "success": "yes"})
    with pytest.raises(jsonschema.ValidationError):     # every shape of optimize is closed too
        _validator("optimize").validate({**_json(capsys, ["optimize", "thesis", "--fit-height", "0.105"]),
                                         "surprise": 1})


def test_keys_and_types_come_from_the_answer_types():
    """Stability.as_json's keys: `scene` a str field, `level_tolerance` written under an `if` (not
    always present), `stiffness` annotated `float | None`; StabilityResult's `notes` only sometimes."""
    keys = schema.answer_keys("levitron.runtime.physics.stability.answer:Stability")
    assert keys["scene"] == (True, "string")
    assert keys["level_tolerance"] == (False, "object?")
    assert keys["stiffness"] == (True, "number?")
    assert keys["resonances"] == (True, "array?")          # None if ... else [...]
    s = schema.schema("stability")
    assert "level_tolerance" in s["properties"] and "level_tolerance" not in s["required"]
    assert s["properties"]["scene_mass"] == {"type": "number"}          # the field's annotation, not declared


def test_a_key_the_code_does_not_type_must_be_declared(monkeypatch):
    from levitron.runtime.cli import schema_keys
    title, sources, declared = schema_keys.VARIANTS["trim"][0]
    monkeypatch.setitem(schema_keys.VARIANTS, "trim",
                        [(title, sources, {k: v for k, v in declared.items() if k != "design"})])
    with pytest.raises(ValueError, match="'design'"):
        schema.schema("trim")
    with pytest.raises(ValueError, match="unknown type"):
        schema.spec_schema("float")
