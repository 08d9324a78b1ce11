"""`levitron field SCENE --at X,Y,Z ...`: B from the model's expansion and the exact B.

B is the generated `field` function (the Laplace expansion of thesis eqs. 2.2.6-2.2.7 to the scene's
order, or the exact 3-D field for a rectangular plate once derive emits it); B_exact is the closed
form of runtime/physics/plates/<kind>.py and runtime/physics/field/exact_field.py (current loops by complete elliptic
integrals, ring magnets after Derby & Olbert 2010, rectangles after Furlani 2001), or null where the
plate has none (expression plates) or the point is singular (on a current filament).
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.words import si, si_unit
from levitron.runtime.ui.validate import number_text
from levitron.runtime.ui.human import Units, lines, sig
from levitron.runtime.ui.plain_text import shown
from levitron.runtime.physics.plates import plate_field
from levitron.runtime.cli.commands.common import model_of

NAME = "field"
HELP = "magnetic field at points: the model's expansion and the exact closed form"
EXAMPLE = 'levitron field ring_magnet --at 0.01,0,0.05'


def add_arguments(parser) -> None:
    parser.add_argument("--at", action="append", default=[], metavar="X,Y,Z",
                        help="a point in the scene's lengths (m in an SI scene; repeatable), e.g. --at 0,0,0.1")


FAR = 1e6      # plate sizes: the farthest point --at takes


def parse_point(text: str) -> list[float]:
    parts = text.split(",")
    try:
        xyz = [number_text(v.strip()) for v in parts]
    except ValueError:
        xyz = []
    if len(xyz) != 3 or not all(math.isfinite(v) for v in xyz):
        raise UserError(f"--at {text!r} is not a point: give three numbers X,Y,Z in {si_unit('m')}, "
                        "e.g. --at 0,0,0.1")
    return xyz


def run(args) -> dict:
    if not args.at:
        raise UserError(f"no point given: add --at X,Y,Z (in {si_unit('m')}, repeatable), e.g. --at 0,0,0.1")
    points = np.array([parse_point(t) for t in args.at])
    model = model_of(args)
    scene = model.scene
    reach = FAR * scene.length_scale
    for t, r in zip(args.at, points):
        if np.max(np.abs(r)) > reach:
            raise UserError(f"--at {t}: the point is more than {FAR:g} plate sizes ({si(reach, 'm', '.3g')}) from "
                            "the plate, where the field is zero in double precision: give a nearer point")
    with np.errstate(all="ignore"):       # an overflow far out is reported as B_exact null
        exact = plate_field(scene.data["plate"], scene.params, points)
    k = scene.field_factor      # the plate's remanence at the scene's temperature (scene/load.py)
    exact = None if exact is None else exact * k
    out = []
    for i, r in enumerate(points):
        B = model.field(r) * k
        entry = {"r": r.tolist(), "B": B.tolist(), "B_exact": None}
        if exact is not None and np.all(np.isfinite(exact[i])):
            entry["B_exact"] = exact[i].tolist()
            scale = float(np.linalg.norm(exact[i]))
            if scale > 0:
                entry["relative_difference"] = float(np.linalg.norm(B - exact[i])) / scale
        if r[2] <= 0:
            entry["note"] = "z <= 0: at or below the plate's (top) face, outside the model's domain"
        out.append(entry)
    result = {"scene": scene.name, "plate": model.manifest.plate,
              "field_order": model.manifest.field_order, "points": out}
    if exact is None:
        result["exact"] = "no closed form for this plate kind"
    if scene.notes:
        result["notes"] = scene.notes
    return result


def human(r: dict, scene=None) -> str:
    """Per point: B of the expansion, the exact B beside it and their relative difference."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    unit = "mT" if u.si else "(scene units)"
    k = 1e3 if u.si else 1.0

    def vec(b):
        return "(" + ", ".join(sig(c * k, 4) for c in b) + f") {unit}"

    rows = []
    for p in r["points"]:
        where = ", ".join(u.length(c) if c else "0" for c in p["r"])
        row = f"B at ({where}): {vec(p['B'])}"
        if p.get("B_exact") is not None:
            row += f"; exact {vec(p['B_exact'])}"
            if p.get("relative_difference") is not None:
                row += f"; the expansion (order {r['field_order']}) differs by {sig(p['relative_difference'], 2)}"
        if p.get("note"):
            row += f" ({p['note']})"
        rows.append(row)
    return lines(*rows, f"exact: {r['exact']}" if r.get("exact") else "",
                 *[f"note: {shown(n, u)}" for n in r.get("notes") or []], u.note)
