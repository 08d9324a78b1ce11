"""The grid of a stability map (runtime/scan/stability_map.py): the axes, their units and their ranges.

`levitron scan` takes the spin and exactly one second axis (tilt, mass or height, see runtime/scan/stability_map.py)
as LO:HI:N ranges; this module parses and checks them (one-line UserErrors saying how to fix them).
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.words import si_unit
from levitron.runtime.ui.validate import count_text, number_text

AXES = ("tilt", "mass", "height")
UNITS = {"spin": "rad/s", "tilt": "rad", "mass": "kg", "height": "fraction of z_s"}
MAX_POINTS = 1_000_000   # grid points of a whole map (and so of one axis): checked before building


def parse_range(text: str, label: str) -> np.ndarray:
    """'LO:HI:N' -> N evenly spaced values from LO to HI (both included); N = 1 needs LO = HI."""
    parts = str(text).split(":")
    if len(parts) != 3:
        raise UserError(f"«{label}» {text!r} must be LO:HI:N (e.g. «{label}=0:1:10»)")
    try:
        lo, hi = number_text(parts[0].strip()), number_text(parts[1].strip())
    except ValueError:
        raise UserError(f"«{label}» {text!r}: LO and HI must be numbers, e.g. «{label}=0:1:10»") from None
    try:
        n = count_text(parts[2].strip())
    except ValueError:
        raise UserError(f"«{label}» {text!r}: N must be a whole number of grid points, e.g. "
                        f"«{label}={parts[0]}:{parts[1]}:10»") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise UserError(f"«{label}» {text!r}: LO and HI must be finite numbers")
    if n < 1:
        raise UserError(f"«{label}» {text!r}: N = {n} must be at least 1 (the number of grid points)")
    if n > MAX_POINTS:
        raise UserError(f"«{label}» {text!r}: N = {n} grid points is too many (a map has at most "
                        f"{MAX_POINTS}); use fewer points")
    if lo > hi:
        raise UserError(f"«{label}» {text!r}: LO = {lo:g} is above HI = {hi:g}; swap them "
                        f"(«{label}={hi:g}:{lo:g}:{n}»)")
    if n == 1 and lo != hi:
        raise UserError(f"«{label}» {text!r}: one grid point needs LO = HI (e.g. «{label}={lo:g}:{lo:g}:1»),"
                        " or pass N >= 2")
    return np.linspace(lo, hi, n)


def check_grid_size(spin: str, other: str, axis: str) -> None:
    """N_spin x N_other <= MAX_POINTS, from the texts LO:HI:N, before any axis is built."""
    try:
        n1, n2 = int(str(spin).split(":")[-1]), int(str(other).split(":")[-1])
    except ValueError:
        return                      # parse_range names the malformed one
    if n1 > 0 and n2 > 0 and n1 * n2 > MAX_POINTS:
        raise UserError(f"«spin» x «{axis}»: {n1} x {n2} = {n1 * n2} grid points is too many (at most "
                        f"{MAX_POINTS}); use fewer points per axis")


def check_axis(axis: str, values: np.ndarray) -> None:
    """The physical range of the second axis (mass > 0, |height| < 1/2; a tilt of 0 is refused: that
    launch lies on the invariant set of thesis 3.2.1, where the ideal top stays at any spin, so its
    row of the map would test nothing)."""
    if axis == "tilt" and np.any(values == 0):
        raise UserError("«tilt» includes 0: a launch with tilt 0 lies on the invariant set (thesis "
                        "3.2.1), where the ideal top stays at any spin, so that row tests nothing; "
                        "start the axis above 0, e.g. «tilt=0.001:0.3:10»")
    if axis == "mass" and values[0] <= 0:
        raise UserError(f"«mass» must be positive ({si_unit('kg')}); got LO = {values[0]:g}")
    if axis == "height" and not (values[0] > -0.5 and values[-1] < 0.5):
        raise UserError(f"«height» is the displacement as a fraction of z_s and must lie strictly "
                        f"between -0.5 and 0.5 (the box is z_s / 2 wide); got {values[0]:g}:{values[-1]:g}")


def pick_axis(specs: dict[str, str | None]) -> tuple[str, str]:
    """Exactly one of --tilt/--mass/--height."""
    given = [(k, v) for k, v in specs.items() if v is not None]
    if len(given) != 1:
        names = ", ".join("--" + k for k, _ in given) if given else "none"
        raise UserError(f"pass exactly one of «tilt», «mass», «height» as the second axis (got {names}), "
                        "e.g. «tilt=0.001:0.3:10»")
    return given[0]
