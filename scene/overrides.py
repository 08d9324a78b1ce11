"""The `--set section.key=value` language: one override read, written and applied (pure Python).

The command line's --set and the API's keyword overrides (`override_text`) both come through
`parse_override`; scene/load.py applies them to the TOML table before it validates.
"""
from __future__ import annotations

import re
from typing import Any

import tomli_w
import tomllib

from .checks import SceneError

_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")   # tab allowed
_BARE_WORD = re.compile(r"[^\"'\\]*\Z")


def parse_override(text: str) -> tuple[list[str], Any]:
    """`section.key=value` -> (["section", "key"], value); value parsed as one TOML value (or a
    bare word without quotes, e.g. plate.kind=disk, or a number with a unit, top.mass=51.5 g, which
    scene/quantity.py converts to SI when the scene is validated). The one reader of overrides: the command
    line's --set and the API's keys (`override_text`) both come through it. A newline or another
    control character is refused (TOML would read the rest as more keys, and drop or change them)."""
    if not isinstance(text, str):
        raise SceneError(f"--set {text!r} is not text: write --set section.key=value")
    shown = text if len(text) <= 80 else text[:77] + "..."
    bad = _CONTROL.search(text)
    if bad:
        raise SceneError(f"--set {shown!r} holds a control character ({bad.group()!r}, e.g. a newline): "
                         "give one key and one value on one line (\\n inside a quoted TOML string)")
    if "=" not in text:
        raise SceneError(f"--set {shown!r} has no '=': write --set section.key=value")
    key, raw = text.split("=", 1)
    path = [p.strip() for p in key.strip().split(".")]
    if not all(path):
        raise SceneError(f"--set {shown!r}: the key {key!r} is malformed; write e.g. top.mass=0.03")
    try:
        parsed = tomllib.loads(f"v = {raw.strip()}")
    except RecursionError:
        raise SceneError(f"--set {shown!r}: the value is nested too deeply: give a number, text "
                         "or a flat list") from None
    except tomllib.TOMLDecodeError:
        if not raw.strip() or not _BARE_WORD.match(raw.strip()):
            raise SceneError(f"--set {shown!r}: the value is not a TOML value; quote a string as "
                             "TOML does, e.g. --set 'plate.phi0=\"z/sqrt(z**2 + 1)\"'") from None
        return path, raw.strip()  # a bare word, e.g. --set plate.kind=disk
    if set(parsed) != {"v"}:
        raise SceneError(f"--set {shown!r}: the value must be one TOML value")
    return path, parsed["v"]


def _toml_value(value: Any, key: str) -> str:
    """One TOML value on one line, written by tomli_w (arrays inline)."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v, key) for v in value) + "]"
    if isinstance(value, dict):
        raise SceneError(f"{key}: a table is not one value: give each key of it separately "
                         f"({key}.<name>=...)")
    try:
        return tomli_w.dumps({"v": value})[len("v = "):].strip()
    except TypeError:
        raise SceneError(f"{key} = {value!r}: a {type(value).__name__} is not a scene value: give a "
                         "number, text, true/false or a list of them") from None


def override_text(key: str, value: Any) -> str:
    """The `--set` text of scene key `key` (e.g. "top.mass") set to `value`, written by a TOML
    writer, never by string formatting: quotes, backslashes and newlines in a value stay inside
    it. `parse_override(override_text(k, v))` gives back (k.split("."), v)."""
    if not isinstance(key, str) or not re.fullmatch(r"[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*", key):
        raise SceneError(f"scene key {key!r} is not a key: write section.key, e.g. top.mass")
    return f"{key}={_toml_value(value, key)}"


def apply_override(data: dict, text: str) -> None:
    """Apply one `--set section.key=value` to the scene's table. A list of tables (a compound
    plate's [[plate.parts]]) is entered by its 0-based index: plate.parts.1.radius=0.02."""
    keys, value = parse_override(text)
    node: Any = data
    for k in keys[:-1]:
        if isinstance(node, list):
            node = node[_index(text, k, node)]
        else:
            node = node.setdefault(k, {})
        if not isinstance(node, (dict, list)):
            raise SceneError(f"--set {text!r}: {k!r} is not a section")
    if isinstance(node, list):
        raise SceneError(f"--set {text!r}: {keys[-2]!r} is a list of tables: name a key inside "
                         f"one of them, e.g. {'.'.join(keys[:-1])}.0.<key>=...")
    node[keys[-1]] = value


def _index(text: str, k: str, items: list) -> int:
    if not k.isdigit() or int(k) >= len(items):
        raise SceneError(f"--set {text!r}: {k!r} is not an index of a list of {len(items)} tables; "
                         f"use 0..{len(items) - 1}")
    return int(k)
