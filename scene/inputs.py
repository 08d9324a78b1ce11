"""The input hash of a generated model: what the generated files depend on (pure Python).

The hash covers the scene's physical structure (plate kind, formulas, field, model; numbers that become
runtime parameters are left out, so `--set top.mass=...` needs no new derivation, but every
structural decision a plate kind declares, e.g. the ring magnet's "hollow: r_in > 0", is in:
scene/plates/), the source of all of derive/ (code and templates) and the versions of sympy and casadi.
The runtime computes the same hash without importing sympy, to tell whether generated/<scene>/ is current.
Not the scene's name: the model is found by its physics, whatever the scene is called (the name only
labels the generated files' banner and manifest).
"""
from __future__ import annotations

import copy
import hashlib
import json
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from . import plates
from .constants import MU0
from .keys import FRICTION_KEYS, TEMPERATURE_KEY, TILT_KEYS_NAMES
from .load import spelled_alike
from .paths import DERIVE_DIR
from .plates.expression import Z_RANGE


def tool_versions() -> dict[str, str]:
    out = {}
    for pkg in ("sympy", "casadi", "jinja2"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = "absent"
    return out


def hashed_sources() -> list[Path]:
    """Every source of derive/ (code and templates): derive/ is the sympy physics, the emitters and
    the build, all of which shape generated/. The scene language (scene/: reading, checks, error
    messages, this hash) is not hashed: what it decides reaches the hash as the validated scene's
    structure (`structure`), so a better error message leaves every generated model current."""
    return [path for path in sorted(DERIVE_DIR.rglob("*"))
            if path.suffix in (".py", ".j2") and "__pycache__" not in path.parts]


def sources_hash() -> str:
    h = hashlib.sha256()
    for path in hashed_sources():
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
    """The part of a validated scene that changes generated code: numbers become runtime
    parameters, except the plate's structural decisions (their values are in `decisions`) and,
    with an accuracy target (field.tolerance), every number (the chosen order depends on them).
    The physics only: the scene's name, description, units and [reference] are left out, so a
    renamed copy of a scene has its model's hash and uses its model (runtime/model/locate.py)."""
    d = copy.deepcopy(data)
    d.get("plate", {}).pop(TEMPERATURE_KEY.name, None)    # a runtime factor on mu (scene/load.py)
    for table in [d.get("plate", {}), *(d.get("plate", {}).get("parts") or [])]:
        if isinstance(table, dict):
            table.pop(Z_RANGE, None)          # an expression plate's search range: runtime only
    tilted = any([d.get("plate", {}).pop(k, None) is not None for k in TILT_KEYS_NAMES])
    keep_numbers = "order" not in d.get("field", {})
    plate = d.get("plate")
    out = {"field": d.get("field"), "model": d.get("model"),
           "plate": plate if keep_numbers else _strip_numbers(plate),
           "decisions": plates.decisions(plate)}
    if any(k in d.get("top", {}) for k in FRICTION_KEYS):   # air friction: the full model's form
        out["friction"] = True
    offset = "moment_offset" in d.get("top", {})     # the moment at r + d n (derive/mechanics.py)
    askew = "moment_tilt" in d.get("top", {})        # the moment off the axis, in the body
    if tilted or offset or askew:   # a base tilt (an imperfect magnet's model has one too): scene/load.py
        out["tilted"] = True
    if offset:
        out["offset"] = True
    if askew:
        out["askew"] = True
    return out


def input_hash(data: dict) -> str:
    """The hash of `structure(data)`, every source of derive/, the tools' versions and MU0: the one
    number of scene/ that generated code holds (derive/plate_fields/plate.py MU0_SYM); scene/'s
    sources are not hashed (tests/house/test_layers.py holds what derive/ takes from scene/)."""
    payload = {"structure": spelled_alike(structure(data)), "derive": sources_hash(),
               "versions": tool_versions(), "constants": {"MU0": MU0}}
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()
