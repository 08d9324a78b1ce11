"""The input hash of a generated model: what the generated files depend on (pure Python).

The hash covers the scene's structure (plate kind, formulas, field, model; numbers that become
runtime parameters are left out, so `--set top.mass=...` needs no new derivation), the source of
derive/ (code and templates) and the versions of sympy and casadi. The runtime computes the same
hash without importing sympy, to tell whether generated/<scene>/ is current.
"""
from __future__ import annotations

import copy
import hashlib
import json
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

DERIVE_DIR = Path(__file__).resolve().parent


def tool_versions() -> dict[str, str]:
    out = {}
    for pkg in ("sympy", "casadi", "jinja2"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = "absent"
    return out


def sources_hash() -> str:
    h = hashlib.sha256()
    for path in sorted(DERIVE_DIR.rglob("*")):
        if path.suffix in (".py", ".j2") and "__pycache__" not in path.parts:
            h.update(str(path.relative_to(DERIVE_DIR)).encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def _strip_numbers(node):
    if isinstance(node, dict):
        return {k: _strip_numbers(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_strip_numbers(v) for v in node]
    if isinstance(node, (int, float)) and not isinstance(node, bool):
        return "#"
    return node


def structure(data: dict) -> dict:
    """The part of a scene that changes generated code (numbers become runtime parameters)."""
    d = copy.deepcopy(data)
    keep_numbers = "order" not in d.get("field", {})   # an accuracy target depends on the numbers
    plate = d.get("plate")
    return {"name": d.get("name"), "field": d.get("field"), "model": d.get("model"),
            "plate": plate if keep_numbers else _strip_numbers(plate)}


def input_hash(data: dict) -> str:
    payload = {"structure": structure(data), "derive": sources_hash(), "versions": tool_versions()}
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()
