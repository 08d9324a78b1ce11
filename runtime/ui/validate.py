"""Checks of the numbers a user gives, shared by the command line and the Python API.

The CLI parses its options and passes them to the same functions that levitron calls
(runtime.simulate.run.simulate, runtime.scan.stability_map.scan, runtime.design.fit.fit); those functions check their
inputs here, so a NaN spin or a negative sigma is refused with the same one-line UserError
whichever way it came in.
"""
from __future__ import annotations

import math
import numbers

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.words import MARKER, si, si_unit


def _param(label: str) -> str:
    """The setting a label names: the marker's name ("«t_end» (run length)" -> "t_end"), else the label."""
    m = MARKER.match(label)
    return m.group(1) if m else label


def real(value, label: str, *, positive: bool = False, nonnegative: bool = False,
         max_abs: float | None = None, unit: str = "", what: str = "") -> float:
    """`value` as a finite float (not a bool, not text), within the given bounds; `what` names the
    quantity in the messages ("run length", "tolerance"); the UserError carries the setting
    (`param`, from the label's marker), the value, `unit` and the hint."""
    named = si_unit(unit) if unit else ""
    noun = f"{what} in {named}" if what and unit else what or (f"number in {named}" if unit else "number")

    def said_with_unit(v) -> str:
        return si(v, unit, "g") if unit else f"{v:g}"

    def refuse(said, v, problem: str, hint: str):
        raise UserError(f"{label} = {said} {problem}" + (f": {hint}" if hint else ""), param=_param(label),
                        value=v, unit=unit, hint=hint or None)
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        refuse(repr(value), value, "is not a number", f"give a finite {noun}")
    v = float(value)
    if not math.isfinite(v):
        refuse(v, v, f"must be a finite {noun}", "")
    if positive and not v > 0:
        refuse(f"{v:g}", v, f"must be a positive {noun}", "")
    if nonnegative and v < 0:
        refuse(said_with_unit(v), v, "must not be negative", "")
    if max_abs is not None and abs(v) > max_abs:
        refuse(said_with_unit(v), v, f"is beyond +-{said_with_unit(max_abs)}", "give a smaller value")
    return v


def count(value, label: str, *, low: int = 1, high: int | None = None) -> int:
    """A whole number (not a bool, not a float) in [low, high]; the UserError carries the setting
    and the value."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise UserError(f"{label} = {value!r} must be a whole number", param=_param(label), value=value)
    n = int(value)
    if n < low or (high is not None and n > high):
        top = f" and at most {high}" if high is not None else ""
        raise UserError(f"{label} = {n} must be at least {low}{top}", param=_param(label), value=n)
    return n


def axis_values(values, label: str, max_points: int) -> np.ndarray:
    """The values of one grid axis: a non-empty 1-D sequence of finite numbers."""
    if isinstance(values, (str, bytes)) or np.isscalar(values):
        raise UserError(f"{label}: give a list of numbers, not {values!r}")
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise UserError(f"{label}: every value must be a number") from None
    if arr.ndim != 1 or arr.size == 0:
        raise UserError(f"{label}: give a non-empty list of numbers (got shape {arr.shape})")
    if arr.size > max_points:
        raise UserError(f"{label}: {arr.size} values is too many (at most {max_points})")
    if not np.all(np.isfinite(arr)):
        raise UserError(f"{label}: every value must be finite (got {arr[~np.isfinite(arr)][0]})")
    return arr


SD_CUT = 8      # a normal spread's range checked: mean +- SD_CUT sd (a draw beyond it has p < 1e-15)


def spread_range(kind: str, a: float, b: float) -> tuple[float, float, str]:
    """(lo, hi, how) of a launch spread (runtime/scan/launch_odds.py Dist: "fixed" a, "uniform"
    a..b, "normal" mean a, sd b): the values its draws take, a normal's to SD_CUT sd; `how` says
    so in a message ("" for the others)."""
    if kind == "normal":
        return a - SD_CUT * b, a + SD_CUT * b, f" (a normal spread is checked over its mean +- {SD_CUT} sd)"
    return (a, b, "") if kind == "uniform" else (a, a, "")


def temperature(data: dict, lo: float, hi: float, label: str) -> None:
    """The one check of a magnets' temperature (degC), for --temperature, the scene key and every
    launch spread alike: the scene reader's (scene/load.py temperature_factors: above absolute
    zero, and each magnet's remanence factor 1 + alpha (T - 20) positive), applied at both ends of
    [lo, hi] (each factor is linear in T, so positive at both ends is positive between them)."""
    from levitron.scene.load import SceneError, temperature_factors
    for T in (lo, hi):
        try:
            temperature_factors({**data, "temperature": float(T)})
        except SceneError as exc:
            raise UserError(f"{label}: {exc}") from None


def shown(text) -> str:
    """A user's text (a path, a name) as a message shows it: as written, or quoted with its escapes
    when it holds a newline or another control character (the message stays one line)."""
    s = str(text)
    return s if s.isprintable() else repr(s)


def number_text(text: str) -> float:
    """The one reading of a number typed as text (a flag's value, a spread, a --vary box, a CSV
    cell): float() without Python's extensions of the number syntax, which a TOML scene, a CSV
    reader or a shell user does not mean: a '_' between digits ("0.1_065" read as 0.1065) or
    non-ASCII digits ("١٢"); ValueError for those, as float() gives for any other non-number."""
    if not isinstance(text, str):
        raise ValueError(text)
    if "_" in text or not text.isascii():
        raise ValueError(text)
    return float(text)


def count_text(text: str) -> int:
    """A whole number typed as text, read as number_text reads one: int() without '_' or
    non-ASCII digits; ValueError otherwise."""
    if not isinstance(text, str) or "_" in text or not text.isascii():
        raise ValueError(text)
    return int(text)
