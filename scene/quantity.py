"""Numbers with units as people type them: "51.5 g", "30 Hz", "1800 rpm", "3 mm", "0.39 T", "2 %".

A scene value (a TOML string or a `--set key=value`), a command-line number flag and an API
keyword may be a quantity: one number and one unit expression. It is converted once, at the edge,
to the SI unit of its key (scene/keys.py, the plate kinds' keys) or setting (`SETTING_UNITS`);
a bare number is SI as it always was and never comes here. The text is checked first (`SHAPE`:
one number, unit names joined by ' ', '*', '/', integer powers, '%'): nothing else reaches pint's
parser and nothing is ever evaluated. pint (one UnitRegistry, made on the first quantity: a scene
without units never imports it) reads the unit; the arithmetic is exact: the typed decimal times
the conversion factor as a rational times a power of 2 pi (rpm: 2 pi / 60, deg: 2 pi / 360),
rounded once, so "51.5 g" is the double 0.0515 and "1800 rpm" the double 2 pi 30.

A spin (rad/s) given as a frequency without an angle (Hz, 1/s, 1/min) is cycles per time: 30 Hz is
2 pi 30 rad/s, not the 30 rad/s that pint's dimensionless radian would give. A relative key
(`RELATIVE`) takes "%" or "ppm"; other keys without a unit take no unit. A dimensionless scene
takes no unit at all. Every problem is one SceneError line.
"""
from __future__ import annotations

import functools
import math
import re
from fractions import Fraction

from .checks import SceneError
from .keys import (FIELD_KEYS, LAUNCH_KEYS, PRODUCTION_KEYS, REFERENCE_KEYS, SCENE_KEYS, TEMPERATURE_KEY, TILT_KEYS,
                   TOP_KEYS, UNITS)

__all__ = ["RELATIVE", "SETTING_UNITS", "SHAPE", "Typed", "convert_scene", "has_unit", "is_si_scene", "setting_value",
           "si_value", "typed_setting"]

_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_NAME = r"(?:[A-Za-zµμΩ°]+|%)(?:(?:\^|\*\*)-?\d+)?"
# one number, then unit names joined by ' ', '*', '/' (a leading "1/" allowed), each with an integer power
SHAPE = re.compile(rf" *({_NUM}) *((?:1 */ *)?{_NAME}(?: *[*/]? *{_NAME})*) *\Z")     # spaces only: no newline
_LOOKS_NUMERIC = re.compile(rf"\s*{_NUM}")
_BARE = re.compile(rf"\s*{_NUM}\s*")
TWO_PI = Fraction(2 * math.pi)      # the double 2 pi, exactly: "30 Hz" is the double 2 * math.pi * 30
G_SI = (9.0, 10.5)                  # m/s^2: the g of an SI scene (scene/keys.py `units`, runtime/ui/human.py)
RELATIVE = frozenset({"field.tolerance", "launch.mass", "launch.strength", "tol"})
# the number flags of the command line and keywords of the API, by setting name -> SI unit
SETTING_UNITS = {"spin": "rad/s", "height": "m", "fit_height": "m", "z_star": "m", "offset": "m", "box": "m",
                 "t_end": "s", "success_time": "s", "step": "s", "scheduler_timeout": "s", "tilt": "rad",
                 "tilt_azimuth": "rad", "base_tilt": "rad", "temperature": "degC", "tol": "",
                 "h": "s", "azimuth": "rad"}      # the API's names of step and tilt_azimuth
_ALSO = {"kg": "g", "m": "mm or cm", "s": "ms or min", "rad/s": "Hz or rpm", "rad": "deg", "T": "mT",
         "degC": "K", "": "% or ppm", "m/s^2": "cm/s^2", "1/K": "%/K", "A m^2": "mA m^2", "kg m^2": "g cm^2"}
_FORMULAS = {("expression", "phi0"), ("expression", "bz")}     # formula text, never a quantity
HEAVY_KG, LONG_M = 1.0, 1.0         # a top over 1 kg or a length over 1 m: grams or millimetres meant?


@functools.lru_cache(maxsize=1)
def _registry():
    """The one UnitRegistry of the process, made on the first quantity (pint loads in ~0.3 s)."""
    import pint
    return pint.UnitRegistry()


def _smooth(n: int) -> bool:
    for p in (2, 3, 5):
        while n % p == 0:
            n //= p
    return n == 1


def _exact(factor: float, turns: int) -> Fraction:
    """The conversion factor as the rational r (2 pi)^k it stands for, r of a 2-3-5-smooth
    denominator (1/1000, 1/60, 1/360), else the double itself; `turns`: one more power of 2 pi."""
    for k in (0, 1, -1):
        r = Fraction(factor / float(TWO_PI) ** k).limit_denominator(10 ** 12)
        if r and _smooth(r.denominator) and math.isclose(float(r * TWO_PI ** k), factor, rel_tol=1e-15):
            return r * TWO_PI ** (k + turns)
    return Fraction(factor) * TWO_PI ** turns


def si_value(text: str, unit: str, name: str, *, relative: bool = False) -> float:
    """`text` ("51.5 g") as a float in the SI unit `unit` ("kg"; "" for a pure number) of the key
    or setting `name`; SceneError, one line, for anything else."""
    shown = text if len(text) <= 40 else text[:37] + "..."
    m = SHAPE.match(text) if len(text) <= 100 else None
    if m is None:
        raise SceneError(f"{name} = {shown!r} is not a number with a unit: write one number and one unit, "
                         f"e.g. {_example(unit)}")
    number, spelt = m.group(1), m.group(2)
    if not unit and not relative:
        raise SceneError(f"{name} = {shown!r}: {name} is a plain number and takes no unit: give the number alone")
    ureg = _registry()
    import pint
    try:
        given = ureg.parse_units(spelt)
    except (pint.errors.PintError, ValueError, TypeError, AttributeError, SyntaxError):
        raise SceneError(f"{name} = {shown!r}: {spelt!r} is not a unit pint knows: give {name} in "
                         f"{_named(unit)}, e.g. {_example(unit)}") from None
    target = ureg.parse_units(unit.replace("1/K", "1/kelvin") or "dimensionless")
    if unit == "degC" or given.dimensionality == ureg.kelvin.dimensionality:
        return _temperature(ureg, number, given, target, name, shown, unit)
    f_given, root_given = ureg.get_root_units(given)
    f_target, root_target = ureg.get_root_units(target)
    turns = 0
    if root_given != root_target and unit == "rad/s" and root_given == ureg.parse_units("1/second"):
        turns = 1       # a frequency without an angle (Hz): cycles per time, 2 pi rad each
    elif root_given != root_target and not unit:
        raise SceneError(f"{name} = {shown!r}: {spelt!r} is not a fraction: give {name} as a plain number, "
                         "in % or in ppm")
    elif root_given != root_target:
        raise SceneError(f"{name} = {shown!r}: {spelt!r} does not convert to {_named(unit)}, the unit of "
                         f"{name}: give it in {_named(unit)} or {_ALSO.get(unit, 'a unit of the same kind')}")
    return float(Fraction(number) * _exact(f_given / f_target, turns))


def _temperature(ureg, number, given, target, name, shown, unit) -> float:
    if unit != "degC" or given.dimensionality != target.dimensionality:
        raise SceneError(f"{name} = {shown!r}: a temperature is not {_named(unit)}, the unit of {name}: "
                         f"give it in {_named(unit)}")
    if given == target:
        return float(Fraction(number))
    if given == ureg.kelvin:
        return float(Fraction(number) - Fraction("273.15"))
    return float(ureg.Quantity(float(Fraction(number)), given).to(target).magnitude)


def _named(unit: str) -> str:
    return unit or "a plain number"


def _example(unit: str) -> str:
    also = _ALSO.get(unit, unit).split(" or ")[0]
    return f"'51.5 {also}'" if also else "'0.1'"


def has_unit(text) -> bool:
    """`text` is one number and a unit ("30 Hz", "30Hz"), the shape `si_value` reads."""
    return isinstance(text, str) and len(text) <= 100 and SHAPE.match(text) is not None


class Typed(float):
    """A setting's SI value that was typed with a unit (`text`): a dimensionless scene refuses it."""

    text: str = ""


def typed_setting(text: str, name: str) -> Typed:
    """`setting_value` remembering what was typed."""
    out = Typed(setting_value(text, name))
    out.text = text
    return out


def setting_value(text: str, name: str) -> float:
    """A number flag's or API keyword's text with a unit ("30 Hz" for spin) in the setting's SI unit."""
    if name not in SETTING_UNITS:
        raise SceneError(f"{name} = {text!r} is not a number: give a number (this setting takes no unit)")
    return si_value(text, SETTING_UNITS[name], name, relative=name in RELATIVE)


# ---------------------------------------------------------------- a scene's values

def is_si_scene(data: dict) -> bool:
    """The scene's `units` when it states them, else SI when 9 <= g <= 10.5 (scene/keys.py `units`)."""
    stated = data.get("units")
    if stated in UNITS:
        return stated == "SI"
    g = data.get("g", 9.81)
    return isinstance(g, (int, float)) and not isinstance(g, bool) and G_SI[0] <= g <= G_SI[1]


def _tables(data: dict):
    """(place, table, {key: SI unit}, kind name) of every table of the scene that holds numbers."""
    from . import plates
    from .plates.expression import Z_RANGE

    def units(keys):
        return {k.name: k.unit for k in keys}
    yield "", data, units(SCENE_KEYS), ""
    for section, keys in (("top", TOP_KEYS), ("reference", REFERENCE_KEYS), ("field", FIELD_KEYS),
                          ("launch", LAUNCH_KEYS), ("production", PRODUCTION_KEYS)):
        if isinstance(data.get(section), dict):
            yield section, data[section], units(keys), ""
    plate = data.get("plate")
    parts = [("plate", plate)] if isinstance(plate, dict) else []
    if parts and isinstance(plate.get("parts"), list):
        parts += [(f"plate.parts.{i}", p) for i, p in enumerate(plate["parts"]) if isinstance(p, dict)]
    for where, table in parts:
        kind = plates.KINDS.get(table.get("kind")) if isinstance(table.get("kind"), str) else None
        keyed = {**units(TILT_KEYS), TEMPERATURE_KEY.name: TEMPERATURE_KEY.unit, Z_RANGE: "m",
                 **(units(kind.keys) if kind else {})}
        yield where, table, keyed, kind.name if kind else ""


def _quantity(value, unit: str, name: str, si: bool, relative: bool):
    """`value` converted when it is text that starts like a number (anything else: the validator's)."""
    if isinstance(value, list):
        return [_quantity(v, unit, name, si, relative) for v in value]
    if (not isinstance(value, str) or not _LOOKS_NUMERIC.match(value) or _BARE.fullmatch(value)
            or not (unit or relative)):
        return value        # not a quantity: the validator's to accept or refuse, as before
    if not si:
        raise SceneError(f"{name} = {value[:40]!r}: this scene is dimensionless (units = \"dimensionless\", or g "
                         "outside 9..10.5): give the number in the scene's own units, without a unit")
    return si_value(value, unit, name, relative=relative)


def convert_scene(data: dict) -> list[str]:
    """Every quantity text of the scene (a TOML table) replaced, in place, by its SI float; the
    warnings (one line each) for a bare SI number that reads as grams or millimetres meant."""
    if isinstance(data.get("g"), str) and data.get("units") != "dimensionless":
        data["g"] = _quantity(data["g"], "m/s^2", "g", True, False)
    si = is_si_scene(data)
    warnings = []
    for where, table, keyed, kind in _tables(data):
        for key, unit in keyed.items():
            name = f"{where}.{key}" if where else key
            if key not in table or (kind, key) in _FORMULAS:
                continue
            value = table[key]
            table[key] = _quantity(value, unit, name, si, name in RELATIVE)
            if si and table[key] is value:
                warnings += _implausible(name, value, unit)
    return warnings


def _implausible(name: str, value, unit: str) -> list[str]:
    """A warning for a bare number that is heavy or long for a levitron in kg or m but plausible in g or mm."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return []
    size = abs(value)        # an int too large for a double is no top's either: the validator's
    if name == "top.mass" and HEAVY_KG < size <= 1000 * HEAVY_KG:
        return [f"warning: {name} = {value:g} kg is heavy for a top: did you mean «{value:g} g»? (a number "
                "without a unit is SI)"]
    if unit == "m" and LONG_M < size <= 1000 * LONG_M and not name.startswith("launch."):
        return [f"warning: {name} = {value:g} m is long for a levitron: did you mean «{value:g} mm»? (a number "
                "without a unit is SI)"]
    return []
