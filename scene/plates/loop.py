"""A circular current loop in z = 0: scene keys and resolver."""
from __future__ import annotations

from ..checks import number, one_of
from ..constants import MU0
from .base import Context, Key, PlateKind, drawn_length


def resolve(table: dict, ctx: Context) -> dict:
    """B at the centre of a loop is mu0 I / (2 a) (Jackson eq. 5.40)."""
    a = number(table, "radius", ctx.where, positive=True)
    key = one_of(table, ("current", "center_field"), ctx.where, "A, or T at the centre")
    if key == "current":
        cur = number(table, "current", ctx.where, nonzero=True)
    else:
        cur = 2 * a * number(table, "center_field", ctx.where, nonzero=True) / MU0
    return {"a": a, "current": cur}


def outline(table: dict) -> dict:
    """A wire of its radius in z = 0."""
    a = drawn_length(table, "radius")
    return {"kind": "loop", "r_out": a, "r_in": a, "thickness": 0.0}


KIND = PlateKind(
    name="loop",
    doc="circular current loop of radius a in z = 0 (counter-clockwise seen from +z for I > 0)",
    keys=(Key("radius", "m", "loop radius a"),
          Key("current", "A", "current I"),
          Key("center_field", "T", "B at the centre instead of I (I = 2 a B / mu0)")),
    resolve=resolve,
    length_keys=("a",),
    units={"current": "A"},
    example='kind = "loop"\nradius = 0.05\ncurrent = 1000.0',
    outline=outline,
    quarter_turn=None,
    exact_field=None,
)
