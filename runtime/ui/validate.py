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
from levitron.runtime.words import MARKER, setting, si, si_unit


def _param(label: str) -> str:
    """The setting a label names: the marker's name ("«t_end» (run length)" -> "t_end"), else the label."""
    m = MARKER.match(label)
    return m.group(1) if m else label


def real(value, label: str, *, positive: bool = False, nonnegative: bool = False,
         max_abs: float | None = None, unit: str = "", what: str = "", hint: str | None = None) -> float:
    """`value` as a finite float (not a bool, not text), within the given bounds; `what` names the
    quantity in the messages ("run length", "tolerance"); `hint` (how to fix it, e.g. "pass e.g.
    «t_end=1»") ends every refusal's sentence. The UserError carries the setting (`param`, from the
    label's marker), the value, `unit` and the hint (without one given, the problem's own fix)."""
    named = si_unit(unit) if unit else ""
    noun = f"{what} in {named}" if what and unit else what or (f"number in {named}" if unit else "number")

    def said_with_unit(v) -> str:
        return si(v, unit, "g") if unit else f"{v:g}"

    def refuse(said, v, problem: str, fix: str, shown: bool = False):
        text = f"{label} = {said} {problem}" + (f": {hint or fix}" if hint or shown else "")
        raise UserError(text, param=_param(label), value=v, unit=unit, hint=hint or fix)
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        refuse(repr(value), value, "is not a number", f"give a finite {noun}", shown=True)
    v = float(value)
    if not math.isfinite(v):
        refuse(v, v, f"must be a finite {noun}", f"give a finite {noun}")
    if positive and not v > 0:
        refuse(f"{v:g}", v, f"must be a positive {noun}", f"give a positive {noun}")
    if nonnegative and v < 0:
        refuse(said_with_unit(v), v, "must not be negative", f"give a {noun} of at least 0")
    if max_abs is not None and abs(v) > max_abs:
        refuse(said_with_unit(v), v, f"is beyond +-{said_with_unit(max_abs)}", "give a smaller value", shown=True)
    return v


def count(value, label: str, *, low: int = 1, high: int | None = None, hint: str | None = None) -> int:
    """A whole number (not a bool, not a float) in [low, high]; the UserError carries the setting,
    the value and the hint (`hint`, else the range to give), and ends its sentence with a given hint."""
    top = f" and at most {high}" if high is not None else ""
    fix = hint or f"give a whole number of at least {low}{top}"
    end = f": {hint}" if hint else ""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise UserError(f"{label} = {value!r} must be a whole number{end}", param=_param(label), value=value,
                        hint=fix)
    n = int(value)
    if n < low or (high is not None and n > high):
        raise UserError(f"{label} = {n} must be at least {low}{top}{end}", param=_param(label), value=n, hint=fix)
    return n


# ---- one check per setting: the command line calls these (or the runtime function that calls
# them), the API reaches them through the same runtime functions, so both faces say one sentence

def run_length(value, name: str = "t_end") -> float:
    """A run length (s): a positive finite time (simulate, scan, launch, an integrator's budget)."""
    return real(value, f"«{name}»", positive=True, unit="s", what="run length", hint=f"pass e.g. «{name}=1»")


def height(value, name: str = "height") -> float:
    """A hover height (m) above the plate: a positive finite length (stability, modes)."""
    return real(value, f"«{name}»", positive=True, unit="m", what="height",
                hint="pick a height above the plate, inside the stable band (`«levitron=equilibrium»` gives it)")


def spin_rate(value, name: str = "spin") -> float:
    """A spin rate (rad/s) that must be positive (the linear modes at a spin)."""
    return real(value, f"«{name}»", positive=True, unit="rad/s", what="spin rate",
                hint="pass a spin inside the stable interval (`«levitron=stability»` gives it)")


def tolerance(value, name: str = "tol") -> float:
    """An integrator's tolerance: a positive finite number (its upper bound is the budget's)."""
    return real(value, f"«{name}»", positive=True, what="tolerance", hint=f"pass e.g. «{name}=1e-8»")


def workers(value, name: str = "workers") -> int:
    """A number of worker processes: a whole number of at least 1 (1: serial)."""
    return count(value, f"«{name}»", low=1)


def launch_count(value, high: int, name: str = "n") -> int:
    """A number of launches: a whole number from 1 to `high`, as text quoted ("n='4'")."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 1 <= value <= high:
        raise UserError(f"{setting(name, repr(value))} must be a whole number of launches from 1 to {high}",
                        param=name, value=value, hint=f"give a whole number from 1 to {high}")
    return int(value)


def random_seed(value, name: str = "seed") -> int:
    """A random seed: a whole number >= 0, as text quoted ("seed='1'")."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 0:
        raise UserError(f"{setting(name, repr(value))} must be a whole number >= 0", param=name, value=value,
                        hint="give a whole number of at least 0")
    return int(value)


def launch_settings(chosen, max_n: int) -> None:
    """The settings of a launch request that need no model (n, seed, the times, tol, workers),
    checked when the request is made (runtime/scan/launch_odds.py Request.of), so that a launch, a
    trim and a launch-odds design refuse them as they are, before any model is built."""
    checks = {"n": lambda v: launch_count(v, max_n), "seed": random_seed, "t_end": run_length, "tol": tolerance,
              "success_time": lambda v: real(v, "«success_time»", positive=True, unit="s", what="time"),
              "workers": workers}
    for key, check in checks.items():
        if chosen.get(key) is not None:
            check(chosen[key])


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
