"""An axially magnetised ring or cylinder magnet, top face in z = 0: scene keys and resolver."""
from __future__ import annotations

from ..checks import SceneError, number
from .base import (Context, Decision, Key, MAGNETIZATION_KEYS, PlateKind, STRENGTH_UNITS, drawn_length,
                   magnetization)


def hollow(table: dict) -> bool:
    """r_in > 0: a ring (outer cylinder minus inner one, parameter plate_r_in); else solid."""
    return float(table.get("r_in", 0.0)) > 0


def resolve(table: dict, ctx: Context) -> dict:
    where = ctx.where
    r_out = number(table, "r_out", where, positive=True)
    r_in = number(table, "r_in", where, default=0.0)
    if r_in < 0 or r_in >= r_out:
        raise SceneError(f"{where}.r_in = {r_in} must satisfy 0 <= r_in < r_out = {r_out}: "
                         "make the inner radius smaller (0 for a solid cylinder)")
    out = {"r_out": r_out, "thickness": number(table, "thickness", where, positive=True),
           "magnetization": magnetization(table, ctx)}
    if hollow(table):
        out["r_in"] = r_in
    return out


def outline(table: dict) -> dict:
    """A ring filling -thickness <= z <= 0."""
    return {"kind": "ring", "r_out": drawn_length(table, "r_out"), "r_in": drawn_length(table, "r_in"),
            "thickness": drawn_length(table, "thickness")}


KIND = PlateKind(
    name="ring_magnet",
    doc="axially magnetised ring (or solid cylinder) magnet, -thickness <= z <= 0",
    keys=(Key("r_out", "m", "outer radius"),
          Key("r_in", "m", "inner radius, 0 <= r_in < r_out (default 0: a solid cylinder)"),
          Key("thickness", "m", "height t; the magnet fills -t <= z <= 0"),
          *MAGNETIZATION_KEYS),
    resolve=resolve,
    decisions=(Decision("hollow", "r_in > 0: the inner cylinder's field is subtracted "
                        "(parameter plate_r_in)", hollow),),
    length_keys=("r_out", "r_in", "thickness"),
    units=STRENGTH_UNITS,
    example='kind = "ring_magnet"\nr_out = 0.06\nr_in = 0.03\nthickness = 0.02\nremanence = 0.39',
    outline=outline,
    quarter_turn=None,
    exact_field=None,
)
