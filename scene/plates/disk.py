"""A thin magnetised disk (thesis eq. 2.2.11 with w = 0): scene keys and resolver."""
from __future__ import annotations

from ..checks import number
from .base import Context, Key, PlateKind, STRENGTH_KEYS, STRENGTH_UNITS, drawn_length, strength_rho


def resolve(table: dict, ctx: Context) -> dict:
    return {**strength_rho(table, ctx), "a": number(table, "radius", ctx.where, positive=True)}


def outline(table: dict) -> dict:
    """A thin ring without a hole in z = 0."""
    return {"kind": "ring", "r_out": drawn_length(table, "radius"), "r_in": 0.0, "thickness": 0.0}


KIND = PlateKind(
    name="disk",
    doc="thin magnetised disk in z = 0 (the annulus without hole), thesis eq. 2.2.11 with w = 0",
    keys=(Key("radius", "m", "radius a"), *STRENGTH_KEYS),
    resolve=resolve,
    length_keys=("a",),
    units=STRENGTH_UNITS,
    example='kind = "disk"\nradius = 0.10\nmurho = -0.0026',
    outline=outline,
    quarter_turn=None,
    exact_field=None,
)
