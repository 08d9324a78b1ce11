"""A uniformly magnetised rectangular plate centred on the axis (block or thin layer), optionally
with a centred circular through-hole (the commercial Levitron's base: a ferrite block with a hole)."""
from __future__ import annotations

from collections.abc import Mapping

from ..checks import SceneError, number
from .base import (
    STRENGTH_UNITS,
    MAGNETIZATION_KEYS,
    STRENGTH_KEYS,
    Context,
    Decision,
    Key,
    PlateKind,
    drawn_length,
    magnetization,
    strength_rho,
)


def block(table: dict) -> bool:
    """thickness > 0: a block magnet (two charged faces, magnetisation); else a thin dipole layer."""
    return float(table.get("thickness", 0.0)) > 0


def holed(table: dict) -> bool:
    """hole > 0: a centred circular through-hole of radius `hole` (parameter plate_hole), the plate
    minus a cylinder (block) or a disk (thin layer) of the same magnetisation; else none."""
    return float(table.get("hole", 0.0)) > 0


def _hole(table: dict, where: str, sx: float, sy: float) -> dict:
    """{"hole": radius} for a holed plate, {} without a hole (hole = 0 is the plain plate)."""
    hole = number(table, "hole", where, default=0.0)
    if not 0 <= hole < min(sx, sy) / 2:
        raise SceneError(f"{where}.hole = {hole} must satisfy 0 <= hole < {min(sx, sy) / 2:g} (half the "
                         "shorter side): make the hole smaller (0 for none)")
    return {"hole": hole} if holed(table) else {}


def outline(table: dict) -> dict:
    """A rectangle with its sides along x and y, filling -thickness <= z <= 0 (0: a thin layer); its
    hole is r_in."""
    side = drawn_length(table, "side")
    return {"kind": "rect", "half_x": 0.5 * drawn_length(table, "side_x", side),
            "half_y": 0.5 * drawn_length(table, "side_y", side), "r_in": drawn_length(table, "hole"),
            "thickness": drawn_length(table, "thickness")}


_SIDES = ("side_x", "side_y")
_STRENGTHS = ("magnetization", "rho")     # the parameters its part's sign multiplies


def quarter_turn(params: Mapping[str, float], sign: float) -> tuple:
    """(this rectangle, the one a quarter turn about z makes of it): the sides and the other resolved
    parameters, the strengths times `sign` (scene/plates/symmetry.py): a quarter turn swaps the sides."""
    rest = tuple(sorted((k, sign * float(v) if k in _STRENGTHS else float(v))
                        for k, v in params.items() if k not in _SIDES))
    sx, sy = float(params["side_x"]), float(params["side_y"])
    return ((sx, sy), rest), ((sy, sx), rest)


def resolve(table: dict, ctx: Context) -> dict:
    where = ctx.where
    if "side" in table:
        if "side_x" in table or "side_y" in table:
            raise SceneError(f"[{where}] has `side` and `side_x`/`side_y`: give `side` (a square) "
                             "or both `side_x` and `side_y`")
        sx = sy = number(table, "side", where, positive=True)
    else:
        if "side_x" not in table or "side_y" not in table:
            raise SceneError(f"[{where}] needs `side` (a square) or both `side_x` and `side_y` (m): "
                             "add them")
        sx = number(table, "side_x", where, positive=True)
        sy = number(table, "side_y", where, positive=True)
    t = number(table, "thickness", where, default=0.0)
    if t < 0:
        raise SceneError(f"{where}.thickness = {t} is negative: give 0 (a thin layer) or the "
                         "thickness (m)")
    if block(table):
        for bad in ("murho", "dipole_density"):
            if bad in table:
                raise SceneError(f"{where}.{bad} is for a thin layer (thickness = 0): give "
                                 "magnetization or remanence for a block")
        return {"side_x": sx, "side_y": sy, "thickness": t, "magnetization": magnetization(table, ctx),
                **_hole(table, where, sx, sy)}
    for bad in ("magnetization", "remanence"):
        if bad in table:
            raise SceneError(f"{where}.{bad} needs a thickness > 0 (a block): add `thickness`, or "
                             "give murho / dipole_density for a thin layer")
    return {**strength_rho(table, ctx), "side_x": sx, "side_y": sy, **_hole(table, where, sx, sy)}


KIND = PlateKind(
    name="rectangle",
    doc="uniformly z-magnetised rectangular plate centred on the axis, top face in z = 0: a block "
        "(thickness > 0) or a thin dipole layer, with an optional centred circular through-hole; "
        "exact 3-D field in the full model (no expansion; a hole's field is expanded to field.order "
        "about the axis, as an axisymmetric plate's is)",
    keys=(Key("side", "m", "side of a square (or side_x and side_y)"),
          Key("side_x", "m", "side along x"),
          Key("side_y", "m", "side along y"),
          Key("thickness", "m", "height t of a block, -t <= z <= 0 (default 0: a thin layer)"),
          Key("hole", "m", "radius of a centred circular through-hole, 0 <= hole < half the shorter "
              "side (default 0: none)"),
          *MAGNETIZATION_KEYS, *STRENGTH_KEYS),
    resolve=resolve,
    decisions=(Decision("block", "thickness > 0: a block magnet (parameters plate_thickness, "
                        "plate_magnetization) instead of a thin layer (plate_rho)", block),
               Decision("holed", "hole > 0: a cylinder (block) or disk (thin layer) of radius "
                        "plate_hole is taken away", holed)),
    length_keys=("side_x", "side_y", "thickness", "hole"),
    units=STRENGTH_UNITS,
    example='kind = "rectangle"\nside = 0.10\nthickness = 0.02\nremanence = 0.39',
    outline=outline,
    quarter_turn=quarter_turn,
    exact_field=lambda table: not holed(table),     # the block's exact 3-D field; a hole's is expanded
)
