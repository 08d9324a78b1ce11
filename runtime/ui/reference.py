"""Stated reference values (a scene's optional `[reference]` table), shown beside the answers.

A `[reference]` table names its `source` and states any of z_stable (m), spin_interval ([lo, hi],
rad/s), mass_window ([lo, hi], kg) and flight_time (s); z_stable and flight_time may be
[value, uncertainty]. The values describe the scene *as written*: its resolved parameters. A
`--set` or `--temperature` that changes any resolved parameter makes another scene, which the
source does not describe: the value is still shown, marked MODIFIED (`equilibrium thesis --set
top.mass=0.0515` once showed the thesis's 15.68 cm beside a top hovering at 10.65 cm as if it
were the same scene, and then dropped it silently). Where `source` names a scene of scenes/
(e.g. "thesis"), the parameters must also equal that scene's: a copy of thesis.toml with another
top is not the thesis's levitron.
"""
from __future__ import annotations

import math

from levitron.scene.paths import SCENES_DIR
from levitron.scene.load import SceneError, load_scene

RTOL = 1e-12     # resolved parameters equal to round-off: the same scene
KEYS = ("z_stable", "spin_interval", "mass_window", "flight_time")
RANGES = ("spin_interval", "mass_window")
MODIFIED = "reference is for the unmodified scene"
# the works a source names, as a citation at first use (author, year, title)
WORKS = {"thesis": "K. F. Lüskow 2011, Theory and Modeling of Gyroscopes (bachelor thesis, Greifswald)"}


def same_parameters(a: dict, b: dict, rtol: float = RTOL) -> bool:
    """Whether two resolved parameter dicts (scene.load.Scene.params) name the same numbers."""
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
    parameters equal those of every reference scene (module docstring), at the same temperature."""
    try:
        refs = _reference_scenes(scene)
    except SceneError:          # the file changed or the named scene is invalid: no claim
        return False
    return bool(refs) and all(r.plate_kind == scene.plate_kind and same_parameters(r.params, scene.params)
                              and r.data.get("temperature") == scene.data.get("temperature") for r in refs)


def cited(source: str) -> str:
    """The source as a citation: a known work named in full (WORKS), else as written."""
    return f"{source} ({WORKS[source]})" if source in WORKS else source


def stated(scene, key: str) -> dict | None:
    """{"value", "uncertainty", "source", "describes"} of a stated value `key` of the scene's
    `[reference]` table (value a number, or [lo, hi] for RANGES; uncertainty None where not given),
    None where the table does not state it. describes: whether it is for this scene (describes);
    where not, the value is shown marked MODIFIED."""
    table = (getattr(scene, "data", None) or {}).get("reference") or {}
    if key not in table:
        return None
    v = table[key]
    unc = None
    if key in RANGES:
        value = [float(v[0]), float(v[1])]
    elif isinstance(v, list):
        value, unc = float(v[0]), float(v[1])
    else:
        value = float(v)
    return {"value": value, "uncertainty": unc, "source": str(table.get("source", "stated")),
            "describes": describes(scene)}


def percent(ours: float, theirs: float) -> str:
    """The difference of our value from the stated one in percent of the stated one: "+0.38 %"."""
    d = 100 * (ours - theirs) / theirs
    return f"{d:+.2g} %" if abs(d) < 10 else f"{d:+.0f} %"


def rows(scene, answers: dict, u) -> list[tuple[str, str]]:
    """One row per stated value: the key, the stated value (with its uncertainty, its source named
    at first use) and ours with the difference in percent; MODIFIED where it is for another scene.
    answers: z_stable (m), spin_interval, mass_window ([lo, hi]), flight_time (s), each None where
    the page has none."""
    out, named = [], False
    shows = {"z_stable": u.length, "flight_time": u.time, "spin_interval": u.rate, "mass_window": u.mass}
    for key in KEYS:
        ref = stated(scene, key)
        if ref is None:
            continue
        show = shows[key]
        src = ref["source"] if named else cited(ref["source"])
        named = True
        ours = answers.get(key)
        if key in RANGES:
            theirs = f"{show(ref['value'][0])} to {show(ref['value'][1])}"
            mine = ("none" if not ours else f"{show(ours[0])} to {show(ours[1])} ("
                    f"{percent(ours[0], ref['value'][0])}, {percent(ours[1], ref['value'][1])})")
        else:
            theirs = show(ref["value"]) + (f" +/- {show(ref['uncertainty'])}" if ref["uncertainty"] else "")
            mine = "none" if ours is None else f"{show(ours)} ({percent(ours, ref['value'])})"
        mark = "" if ref["describes"] else f"; {MODIFIED}"
        out.append((f"{key.replace('_', ' ')}: {src}", f"{theirs}; here {mine}{mark}"))
    return out
