"""JSON Schemas (draft 2020-12) of every command's `--json` answer, built from the answer types.

Where a command's answer is an answer type's `as_json()` (Stability, Scan, LaunchOdds, Trim, ...), its keys
are read from that method's source: every string key of the dict it returns or assigns, present always
(written unconditionally) or sometimes (inside an `if`, or a `**({...} if ... else {})`); a key's type from
what the code declares: the dataclass field's or the property's annotation where the value is `self.NAME`,
else the literal it is (a dict, a list, a string). What the source cannot tell (a key built elsewhere, a
spread of another dict, the keys the command adds) is declared once in runtime/cli/schema_keys.py in a
short notation; a declaration wins over what is read. A command whose answer may take several shapes
(optimize: a design, a launch-odds design, a fit, a height fit) has one variant a shape (`anyOf`).

Every top level has `additionalProperties: false`: a new key fails the schema until it is declared (and
documented in docs/contract.md); nested objects stay open. Every answer carries `provenance` and
`success` (runtime/cli/main.py). A number that is NaN or infinite is null in the JSON (the contract):
where that may happen the key is declared nullable.

`levitron schema [COMMAND]` prints a schema (runtime/cli/commands/schema.py); `python -m
levitron.runtime.cli.schema [FOLDER]` writes every schema to docs/schemas/COMMAND.json (tests/cli/
test_json_schema.py checks the committed files equal these and validates real outputs against them).
"""
from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import json
import sys
import textwrap
from pathlib import Path

from levitron.runtime.cli.schema_keys import FACE, VARIANTS

DRAFT = "https://json-schema.org/draft/2020-12/schema"
SCALARS = ("number", "integer", "string", "boolean", "array", "object", "null")
_ANNOTATED = {"float": "number", "int": "integer", "str": "string", "bool": "boolean", "dict": "object",
              "list": "array", "tuple": "array", "None": "null"}
OPEN = "..."        # a declared key that lets the top level take keys it does not name (bench's other kinds)


def commands() -> list[str]:
    """The commands with a schema: every command of the command line (they all print JSON)."""
    from levitron.runtime.cli.commands import COMMANDS
    return list(COMMANDS)


def spec_schema(spec) -> dict:
    """A schema from the notation: "number", "string?" (or null), "number|string", "any"; a dict is an
    object with those keys ("~key": not always present); a one-element list an array of that item."""
    if isinstance(spec, dict):
        props, required = _properties(spec)
        out = {"type": "object", "properties": props}
        return {**out, "required": required} if required else out
    if isinstance(spec, list):
        return {"type": "array", "items": spec_schema(spec[0])}
    text = spec.rstrip("?")
    if text == "any":
        return {}
    types = text.split("|") + (["null"] if spec.endswith("?") else [])
    unknown = [t for t in types if t not in SCALARS]
    if unknown:
        raise ValueError(f"schema notation {spec!r}: unknown type {unknown[0]!r} (use one of {', '.join(SCALARS)})")
    return {"type": types[0] if len(types) == 1 else types}


def _properties(spec: dict) -> tuple[dict, list]:
    props, required = {}, []
    for key, sub in spec.items():
        name = key.lstrip("~")
        props[name] = spec_schema(sub)
        if not key.startswith("~"):
            required.append(name)
    return props, required


def annotation_type(text) -> str | None:
    """The notation of an annotation ("float | None" -> "number?"), or None where it names no JSON type."""
    if not isinstance(text, str):
        text = getattr(text, "__name__", str(text))
    types = [_ANNOTATED.get(part.strip().split("[")[0]) for part in text.split("|")]
    if not types or None in types:
        return None
    nullable = "null" in types
    types = list(dict.fromkeys(t for t in types if t != "null"))
    return "|".join(types) + ("?" if nullable else "") if types else None


def _attribute_type(cls, name: str) -> str | None:
    """The notation of answer type `cls`'s field or property `name`, from its annotation."""
    fields = {f.name: f.type for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else {}
    if name in fields:
        return annotation_type(fields[name])
    prop = inspect.getattr_static(cls, name, None)
    if isinstance(prop, property) and prop.fget is not None:
        returned = prop.fget.__annotations__.get("return")
        return None if returned is None else annotation_type(returned)
    return None


def _value_type(cls, node) -> str | None:
    """The notation of a value expression of `as_json`, where the code says it; else None."""
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self":
        return _attribute_type(cls, node.attr)
    if isinstance(node, (ast.Dict, ast.DictComp)):
        return "object"
    if isinstance(node, (ast.List, ast.ListComp, ast.Tuple)):
        return "array"
    if isinstance(node, ast.JoinedStr):
        return "string"
    if isinstance(node, ast.Constant) and type(node.value) in (str, bool, int, float):
        return annotation_type(type(node.value).__name__)
    if isinstance(node, ast.IfExp):
        sides = [_value_type(cls, n) for n in (node.body, node.orelse)]
        if "null" in sides:
            other = next((s for s in sides if s != "null"), None)
            return None if other is None else other.rstrip("?") + "?"
        return sides[0] if sides[0] is not None and sides[0] == sides[1] else None
    if isinstance(node, ast.Constant) and node.value is None:
        return "null"
    return None


def answer_keys(source: str) -> dict[str, tuple[bool, str | None]]:
    """key -> (always present, its notation or None) of the dict an answer type's method returns:
    `source` is "module:Class.method" (method as_json unless named)."""
    module, _, name = source.partition(":")
    cls_name, _, method = name.partition(".")
    cls = getattr(importlib.import_module(module), cls_name)
    tree = ast.parse(textwrap.dedent(inspect.getsource(getattr(cls, method or "as_json"))))
    keys: dict[str, tuple[bool, str | None]] = {}

    def from_dict(node: ast.Dict, always: bool) -> None:
        for k, v in zip(node.keys, node.values):
            if k is None:      # a spread: its keys where it is a literal, else the declaration's
                if isinstance(v, ast.IfExp) and isinstance(v.body, ast.Dict):
                    from_dict(v.body, False)
            elif isinstance(k, ast.Constant) and isinstance(k.value, str):
                keys[k.value] = (always, _value_type(cls, v))

    def visit(stmts, always: bool) -> None:
        for stmt in stmts:
            value = getattr(stmt, "value", None)
            if isinstance(stmt, (ast.Return, ast.Assign)) and isinstance(value, ast.Dict):
                from_dict(value, always)
            elif isinstance(stmt, ast.Assign):
                for target in stmt.targets:
                    if isinstance(target, ast.Subscript) and isinstance(target.slice, ast.Constant) \
                            and isinstance(target.slice.value, str):
                        keys[target.slice.value] = (always, _value_type(cls, value))
            elif isinstance(stmt, (ast.If, ast.For, ast.While, ast.With, ast.Try)):
                visit([s for field in ("body", "orelse", "finalbody") for s in getattr(stmt, field, [])], False)
    visit(tree.body[0].body, True)
    return keys


def variant_schema(command: str, sources: tuple, declared: dict) -> dict:
    """One shape of `command`'s answer: the keys its answer types write, the declared ones, the face's."""
    spec: dict = {}
    for source in sources:
        for key, (always, notation) in answer_keys(source).items():
            if key in declared or f"~{key}" in declared:
                continue
            if notation is None:
                raise ValueError(f"{command}: {source} writes {key!r}, whose type the code does not say: "
                                 "declare it in runtime/cli/schema_keys.py")
            spec[key if always else f"~{key}"] = notation
    spec.update({k: v for k, v in declared.items() if k != OPEN})
    spec.update(FACE)
    props, required = _properties(spec)
    return {"type": "object", "properties": props, "required": required,
            "additionalProperties": OPEN in declared}


def schema(command: str) -> dict:
    """The JSON Schema of `command --json` (draft 2020-12)."""
    from levitron.runtime.cli.main import command_help
    if command not in VARIANTS:
        raise KeyError(f"no schema declared for command {command!r} (runtime/cli/schema_keys.py VARIANTS)")
    shapes = []
    for title, sources, declared in VARIANTS[command]:
        shape = variant_schema(command, sources, declared)
        shapes.append({"title": title, **shape} if len(VARIANTS[command]) > 1 else shape)
    head = {"$schema": DRAFT,
            "title": f"levitron {command} --json", "description": command_help(command)}
    return {**head, **shapes[0]} if len(shapes) == 1 else {**head, "type": "object", "anyOf": shapes}


def text(command: str) -> str:
    """The schema as the file docs/schemas/COMMAND.json holds it."""
    return json.dumps(schema(command), indent=2) + "\n"


def write_all(folder: Path) -> list[Path]:
    """Every command's schema into folder/COMMAND.json (the folder made if needed); returns the files."""
    from levitron.runtime.ui.atomic import write_text
    return [write_text(folder / f"{command}.json", text(command), "schema") for command in commands()]


def default_folder() -> Path:
    """docs/schemas of the source checkout (runtime/ sits at the repository's top level)."""
    return Path(__file__).resolve().parents[2] / "docs" / "schemas"


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    folder = Path(argv[0]) if argv else default_folder()
    for path in write_all(folder):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
