"""The thesis's thin annulus (thesis eq. 2.2.11): scene keys and resolver."""
from __future__ import annotations

from ..checks import SceneError, number
from .base import Context, Key, PlateKind, STRENGTH_KEYS, STRENGTH_UNITS, drawn_length, strength_rho


def resolve(table: dict, ctx: Context) -> dict:
    a = number(table, "radius", ctx.where, positive=True)
    w = number(table, "hole", ctx.where, default=0.0)
    if w < 0:
        raise SceneError(f"{ctx.where}.hole = {w} is negative: give 0 <= hole < radius")
    if w >= a:
        raise SceneError(f"{ctx.where}.hole = {w} is not smaller than {ctx.where}.radius = {a}: "
                         "make the hole smaller than the plate")
    return {**strength_rho(table, ctx), "a": a, "w": w}


def outline(table: dict) -> dict:
    """A thin ring in z = 0 (thesis 2.2.11)."""
    return {"kind": "ring", "r_out": drawn_length(table, "radius"), "r_in": drawn_length(table, "hole"),
            "thickness": 0.0}


KIND = PlateKind(
    name="annulus",
    doc="thin magnetised annulus in z = 0 (a dipole layer), thesis eq. 2.2.11",
    keys=(Key("radius", "m", "outer radius a"),
          Key("hole", "m", "inner radius w, 0 <= hole < radius (default 0)"),
          *STRENGTH_KEYS),
    resolve=resolve,
    length_keys=("a", "w"),
    units=STRENGTH_UNITS,
    example='kind = "annulus"\nradius = 0.10\nhole = 0.03\nmurho = -0.0026',
    outline=outline,
    quarter_turn=None,
    exact_field=None,
)
