"""A plate given by a formula for its on-axis potential or field: scene keys and resolver.

The formula is only checked for type and length here; derive parses it safely
(derive/expr_parse.py, never evaluated as Python) and reports a bad formula as a one-line
SceneError naming plate.phi0 / plate.bz.
"""
from __future__ import annotations

import re

from ..checks import SceneError, number, one_of
from .base import Context, Key, PlateKind

# The functions (name -> number of arguments) and constants a formula may use; derive/expr_parse.py
# maps them to sympy. `abs` is not among them: its derivatives (sign, DiracDelta) have no code.
FUNCTIONS = {"sqrt": 1, "exp": 1, "log": 1, "sin": 1, "cos": 1, "tan": 1, "asin": 1, "acos": 1,
             "atan": 1, "atan2": 2, "sinh": 1, "cosh": 1, "tanh": 1, "asinh": 1, "acosh": 1,
             "atanh": 1}
CONSTANTS = ("pi", "E")
# Names a parameter may not take: the functions, the constants, z, and abs (refused by name).
RESERVED_NAMES = frozenset(FUNCTIONS) | frozenset(CONSTANTS) | {"z", "abs", "Abs"}
MAX_FORMULA = 2000   # characters (derive/expr_parse.py MAX_LENGTH)
MAX_CALL_DEPTH = 6   # function calls nested in function calls (derive/expr_parse.py)
_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
Z_RANGE = "z_range"   # [lo, hi]: the heights where the formula holds (a runtime search range, not derived)


def z_range(table: dict, where: str) -> tuple[float, float] | None:
    """table's z_range as (lo, hi) with 0 < lo < hi, or None where the scene states none."""
    if Z_RANGE not in table:
        return None
    value = table[Z_RANGE]
    how = f"write e.g. {Z_RANGE} = [0.02, 0.06] (heights in m where the formula holds, lo < hi)"
    if not (isinstance(value, list) and len(value) == 2):
        raise SceneError(f"{where}.{Z_RANGE} = {value!r} is not two heights: {how}")
    lo, hi = (number({"v": v}, "v", f"{where}.{Z_RANGE}", positive=True) for v in value)
    if not lo < hi:
        raise SceneError(f"{where}.{Z_RANGE} = {value!r}: the range is empty or reversed: {how}")
    return lo, hi


def resolve(table: dict, ctx: Context) -> dict:
    """phi0 or bz as a formula string; [plate.params] name -> number."""
    where = ctx.where
    key = one_of(table, ("phi0", "bz"), where, "the on-axis potential or on-axis field, in z")
    text = table[key]
    if not isinstance(text, str) or not text.strip():
        raise SceneError(f"{where}.{key} must be a formula in quotes, e.g. "
                         f"{key} = \"b*z/sqrt(z**2 + c**2)\"")
    if len(text) > MAX_FORMULA:
        raise SceneError(f"{where}.{key} is {len(text)} characters long: the limit is {MAX_FORMULA}")
    params = table.get("params", {})
    if not isinstance(params, dict):
        raise SceneError(f"{where}.params must be a table of name = number: write [{where}.params]")
    out = {}
    for name in sorted(params):
        if not _IDENT.match(name) or name in RESERVED_NAMES:
            raise SceneError(f"{where}.params.{name}: not a usable name (letters, digits, '_', "
                             "starting with a letter; not z or a function name): rename it")
        out[name] = number(params, name, f"{where}.params")
    z_range(table, where)
    return out


KIND = PlateKind(
    name="expression",
    doc="on-axis potential phi0(z) or on-axis field bz(z) given as a formula (parsed safely, never "
        "evaluated as Python); the field off the axis by the Laplace expansion",
    keys=(Key("phi0", "T m", "Phi0(z), a formula in z and the names of [plate.params]: numbers, "
              "+ - * / **, pi, E and " + ", ".join(FUNCTIONS) + " (no abs: its derivatives have "
              f"no code); at most {MAX_FORMULA} characters, calls nested at most {MAX_CALL_DEPTH} deep"),
          Key("bz", "T", "B_z on the axis instead (Phi0 = -integral of bz dz must have a closed "
              "form)"),
          Key("params", "", "table name = number: the formula's parameters (runtime parameters "
              "plate_<name>)"),
          Key(Z_RANGE, "m", "[lo, hi]: the heights where the formula holds (optional; default: the "
              "whole search, 1e-4 to 1e4 of the length scale 1); equilibria and bands are searched "
              "inside it, and a band that ends at it says so: it is the formula's end, not physics")),
    resolve=resolve,
    example='kind = "expression"\nphi0 = "b*z/sqrt(z**2 + c**2)"\n\n[plate.params]\nb = 1.0\nc = 0.5',
    outline=None,          # a formula has no shape to draw
    quarter_turn=None,     # the Laplace expansion of an on-axis formula is axisymmetric
    exact_field=None,      # the expansion of its on-axis formula
)


def formulas(table: dict, where: str = "plate") -> list[str]:
    """`where.phi0 = '...'` (or bz) of an expression plate and of every expression part of a
    compound one, shortened for a one-line message; [] for a plate without a formula."""
    found = []
    if table.get("kind") == "expression":
        for key in ("phi0", "bz"):
            text = table.get(key)
            if isinstance(text, str):
                shown = text if len(text) <= 60 else text[:57] + "..."
                found.append(f"{where}.{key} = {shown!r}")
    for i, part in enumerate(table.get("parts") or []):
        if isinstance(part, dict):
            found += formulas(part, f"{where}.parts[{i}]")
    return found
