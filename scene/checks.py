"""SceneError and the small validators that scene.py and the plate registry share (pure Python).

Every problem is one `SceneError` line that names the key, says what is wrong and how to fix it
(docs/contract.md, "Errors").
"""
from __future__ import annotations

import difflib
import math

# A scene number outside this magnitude range is refused: no SI levitron and no dimensionless
# scene (values near 1) needs it, and beyond it products such as A^2 C^2 Omega^4 leave double range.
MAX_MAGNITUDE = 1e12
MIN_MAGNITUDE = 1e-12


class SceneError(ValueError):
    """A scene is wrong; the message names the key, what is wrong and how to fix it."""


def number(section: dict, key: str, where: str, *, positive: bool = False, nonzero: bool = False,
           default: float | None = None, required: bool = True) -> float | None:
    """section[key] as a finite float of sane magnitude (module docstring), or `default`."""
    if key not in section:
        if default is not None or not required:
            return default
        raise SceneError(f"{where}.{key} is missing: add `{key} = <number>` to [{where}]"
                         if where else f"{key} is missing: add `{key} = <number>` to the scene")
    value = section[key]
    name = f"{where}.{key}" if where else key
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(f"{name} = {value!r} is not a number: write e.g. `{key} = 0.1`")
    try:
        value = float(value)
    except OverflowError:
        value = math.inf if value > 0 else -math.inf
    if not math.isfinite(value):
        raise SceneError(f"{name} = {value} is not finite: give a finite number")
    if positive and value <= 0:
        raise SceneError(f"{name} = {value:g} must be positive: give a value > 0")
    if nonzero and value == 0:
        raise SceneError(f"{name} = 0 must be nonzero: give the signed value")
    if value != 0 and not MIN_MAGNITUDE <= abs(value) <= MAX_MAGNITUDE:
        raise SceneError(f"{name} = {value:g} is outside {MIN_MAGNITUDE:g} <= |value| <= "
                         f"{MAX_MAGNITUDE:g}: give SI units, or scale the scene to values near 1")
    return value


def check_keys(section: dict, allowed, where: str) -> None:
    """SceneError for the first key of `section` outside `allowed`, with the nearest allowed key
    when one is close (a typo: `remanance` -> did you mean `remanence`?) and the whole list."""
    unknown = sorted(set(section) - set(allowed))
    if unknown:
        near = difflib.get_close_matches(str(unknown[0]), sorted(allowed), n=1, cutoff=0.75)
        hint = f"did you mean `{near[0]}`? " if near else ""
        raise SceneError(f"[{where}] has unknown key `{unknown[0]}`: {hint}allowed keys are "
                         f"{', '.join(sorted(allowed))}")


def one_of(table: dict, keys: tuple[str, str], where: str, hint: str) -> str:
    """The one key of `keys` that `table` has; SceneError when it has none or both."""
    present = [k for k in keys if k in table]
    if len(present) != 1:
        raise SceneError(f"[{where}] needs exactly one of `{keys[0]}` or `{keys[1]}` ({hint}): "
                         "give one")
    return present[0]
