"""Stated reference values (a scene's optional `[reference]` table), shown only for the scene they describe.

A `[reference]` table (`source = "thesis"`, `z_stable = 0.1568`) states what a source found for the
scene *as written*: its resolved parameters. A `--set` that changes any resolved parameter (the
top's mass, the plate's hole, g, ...) makes another scene, which the source does not describe, so
the value is dropped (`equilibrium thesis --set top.mass=0.0515` used to show the
thesis's 15.68 cm beside a top hovering at 10.65 cm). Where `source` names a scene of scenes/
(e.g. "thesis"), the parameters must also equal that scene's: a copy of thesis.toml with another
top keeps its `[reference]` table but is not the thesis's levitron.
"""
from __future__ import annotations

import math

from levitron.derive.paths import SCENES_DIR
from levitron.derive.scene import SceneError, load_scene

RTOL = 1e-12     # resolved parameters equal to round-off: the same scene


def same_parameters(a: dict, b: dict, rtol: float = RTOL) -> bool:
    """Whether two resolved parameter dicts (derive.scene.Scene.params) name the same numbers."""
    if set(a) != set(b):
        return False
    return all(math.isclose(float(a[k]), float(b[k]), rel_tol=rtol, abs_tol=0.0) for k in a)


def _reference_scenes(scene) -> list:
    """The scenes the reference describes: the file as written, and a scene of scenes/ that the
    source names."""
    out = []
    if scene.path is not None:
        out.append(load_scene(scene.path))
    table = scene.data.get("reference") or {}
    source = str(table.get("source", ""))
    named = SCENES_DIR / f"{source}.toml"
    if source and source.isidentifier() and named.is_file():
        out.append(load_scene(named))
    return out


def describes(scene) -> bool:
    """Whether the scene's `[reference]` values describe this scene: its plate kind and resolved
    parameters equal those of every reference scene (module docstring)."""
    try:
        refs = _reference_scenes(scene)
    except SceneError:          # the file changed or the named scene is invalid: no claim
        return False
    return bool(refs) and all(r.plate_kind == scene.plate_kind and same_parameters(r.params, scene.params)
                              for r in refs)


def stated(scene, key: str) -> dict | None:
    """{"value", "source"} of a stated value `key` of the scene's `[reference]` table when it
    describes this scene (describes), else None."""
    table = (getattr(scene, "data", None) or {}).get("reference") or {}
    if key not in table or not describes(scene):
        return None
    return {"value": float(table[key]), "source": str(table.get("source", "stated"))}
