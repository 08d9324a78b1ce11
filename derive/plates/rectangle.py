"""A uniformly magnetised rectangular plate centred on the axis (block or thin layer)."""
from __future__ import annotations

from ..checks import SceneError, number
from .base import (
    STRENGTH_UNITS,
    MAGNETIZATION_KEYS,
    STRENGTH_KEYS,
    Context,
    Decision,
    Key,
    PlateKind,
    magnetization,
    strength_rho,
)


def block(table: dict) -> bool:
    """thickness > 0: a block magnet (two charged faces, magnetisation); else a thin dipole layer."""
    return float(table.get("thickness", 0.0)) > 0


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
        return {"side_x": sx, "side_y": sy, "thickness": t, "magnetization": magnetization(table, ctx)}
    for bad in ("magnetization", "remanence"):
        if bad in table:
            raise SceneError(f"{where}.{bad} needs a thickness > 0 (a block): add `thickness`, or "
                             "give murho / dipole_density for a thin layer")
    return {**strength_rho(table, ctx), "side_x": sx, "side_y": sy}


KIND = PlateKind(
    name="rectangle",
    doc="uniformly z-magnetised rectangular plate centred on the axis, top face in z = 0: a block "
        "(thickness > 0) or a thin dipole layer; exact 3-D field in the full model (no expansion)",
    keys=(Key("side", "m", "side of a square (or side_x and side_y)"),
          Key("side_x", "m", "side along x"),
          Key("side_y", "m", "side along y"),
          Key("thickness", "m", "height t of a block, -t <= z <= 0 (default 0: a thin layer)"),
          *MAGNETIZATION_KEYS, *STRENGTH_KEYS),
    resolve=resolve,
    decisions=(Decision("block", "thickness > 0: a block magnet (parameters plate_thickness, "
                        "plate_magnetization) instead of a thin layer (plate_rho)", block),),
    length_keys=("side_x", "side_y", "thickness"),
    units=STRENGTH_UNITS,
    can_be_part=False,
    example='kind = "rectangle"\nside = 0.10\nthickness = 0.02\nremanence = 0.39',
)
