"""`levitron info SCENE`: resolved parameters in SI, what is generated, op counts."""
from __future__ import annotations

import math

from levitron.scene import plates
from levitron.scene.plates.symmetry import symmetry
from levitron.scene.constants import MU0

from levitron.runtime.physics.apparatus.friction import decay_times, friction_rates, has_friction
from levitron.runtime.ui.human import Units, lines, sig
from levitron.runtime.ui.plain_text import shown
from levitron.runtime.cli.commands.common import model_of

NAME = "info"
HELP = "resolved parameters (SI), generated parts and functions, operation counts"
EXAMPLE = 'levitron info thesis'


def add_arguments(parser) -> None:
    pass


def run(args) -> dict:
    model = model_of(args)
    scene = model.scene
    params = model.pvals()
    derived = {}
    if "plate_rho" in params:
        rho = params["plate_rho"]
        derived["murho"] = params["mu"] * rho
        derived["dipole_density_A"] = 4 * math.pi * rho / MU0
    m = model.manifest
    return {
        "scene": scene.name,
        "file": str(scene.path),
        "parameters": params,
        "derived_parameters": derived,
        "notes": scene.notes,
        "symmetry": symmetry(scene.data["plate"], params).as_dict(),
        "generated": str(model.folder),
        "input_hash": m.input_hash,
        "plate": m.plate, "coordinates": m.coordinates, "field_order": m.field_order,
        "parts": {k: list(v.states) for k, v in m.parts.items()},
        "functions": {k: {"ops": f.ops, "n_in": f.n_in, "n_out": f.n_out, "doc": f.doc}
                      for k, f in m.functions.items()},
        "taylor": {part: {"function": t.function, "nodes": t.nodes, "max_order": t.max_order}
                   for part, t in m.taylor.items()},
        "decay_times": decay_times(params) if has_friction(model) else None,
        "friction_rates": friction_rates(params) if has_friction(model) else None,
    }


def _taylor(taylor: dict | None) -> str:
    """The parts with Taylor coefficients (derive/emit/taylor.py: integrator taylor), or a "none" line."""
    if not taylor:
        return ("taylor coefficients: none (integrator taylor needs a reduced model whose rhs has "
                "a recurrence for every operation)")
    return "taylor coefficients: " + ", ".join(
        f"{part} ({t['function']}, {t['nodes']} series nodes, orders up to {t['max_order']}: "
        "integrator taylor)" for part, t in taylor.items())


def _air(taus: dict | None, u: Units) -> str:
    """The scene's air friction (derive/friction.py) as decay times, or "" without friction."""
    if not taus:
        return ""
    return "air friction: decay times " + ", ".join(
        f"{name} {u.time(v) if v else 'none'}" for name, v in taus.items())


def _param(name: str, v: float, u: Units, plate_units=None) -> str:
    """One parameter with its unit in the scene's units (plate_units: plates.param_units)."""
    unit = (plate_units or {}).get(name)
    if unit == "m":
        return f"{name} {u.length(v)}"
    if unit:
        return f"{name} {u.value(v, unit, 6)}"
    if name == "m":
        return f"mass {u.mass(v)}"
    if name in ("A", "C"):
        return f"{name} {u.value(v, 'kg m^2')}"
    if name == "g":
        return f"g {u.value(v, 'm/s^2')}"
    if name == "mu":
        return f"moment {u.value(v, 'A m^2')}"
    return f"{name} {sig(v, 6)}"


def human(r: dict, scene=None) -> str:
    """The scene, its parameters (SI names in the JSON), the generated parts and their sizes."""
    u = Units.of_scene(scene) if scene is not None else Units.of(r["parameters"].get("g"))
    plate_units = plates.param_units(scene.data["plate"]) if scene is not None else {}
    # the dipole density (A) goes through mu0, an SI constant: no meaning in a dimensionless scene
    derived = {k: v for k, v in r["derived_parameters"].items() if u.si or k != "dipole_density_A"}
    ops = ", ".join(f"{k} {v['ops']}" for k, v in r["functions"].items())
    parts = ", ".join(f"{k} ({len(v)} states)" for k, v in r["parts"].items())
    return lines(
        f"{r['scene']}: {r['plate']} plate, field order {r['field_order']}, {r['coordinates']} angles",
        "parameters: " + ", ".join(_param(k, v, u, plate_units) for k, v in r["parameters"].items()),
        "derived: " + ", ".join(f"{k} {sig(v, 6)}" for k, v in derived.items()) if derived else "",
        f"parts: {parts}",
        _air(r.get("decay_times"), u),
        f"operations per call: {ops}",
        _taylor(r.get("taylor")),
        *[f"note: {shown(n, u)}" for n in r.get("notes") or []],
        # an axisymmetric plate's symmetry goes without saying (the thesis's case)
        f"symmetry: {r['symmetry']['summary']}" if r.get("symmetry", {}).get("name", "axial") != "axial" else "",
        f"generated: {r['generated']} (input hash {r['input_hash'][:12]})",
        u.note)
