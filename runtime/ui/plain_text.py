"""A sentence's quantities in the units a person reads: the plain view's renderer of the markers.

The runtime writes a number with its SI unit as a quantity marker (runtime/words.py `si`:
"‹0.157391|m›"). The JSON shows it in SI ("0.157391 m"); a plain view, a message, a repr and the
report show it here, once, from the marker itself (never by re-reading finished text):

    shown("at z_s = ‹0.157391|m›", Units(si=True))       -> "at z_s = 15.74 cm"
    shown("mass in ‹[0.0494, 0.0515]|kg›", si)           -> "mass in 49.4-51.5 g"
    shown("at z_s = ‹0.157391|m›", Units(si=False))      -> "at z_s = 0.1574"

Lengths and masses (and their spans and lists) in the scene's display units (cm, mm, g; bare in a
dimensionless scene); any other unit as written in an SI scene, and in a dimensionless one as the
scene shows it (rates in rad/time, times in time units, the rest bare). A unit named alone ("in
‹|m›") is the scene's name for it. Setting markers («t_end») are left for the face to word.

`said(**sentences)` keeps an answer's sentences as written (markers and all) beside the fields
that the API words for its face (runtime/words.py `speak` leaves a mapping proxy as it is), so that
the answer's own views render them from the markers.
"""
from __future__ import annotations

import types

from levitron.runtime.ui.human import Units, span
from levitron.runtime.words import QUANTITY

__all__ = ["NOTHING_SAID", "kept", "said", "shown"]

NOTHING_SAID = types.MappingProxyType({})


def said(**sentences) -> types.MappingProxyType:
    """The sentences as written, kept from the face's wording (lists kept as tuples)."""
    return types.MappingProxyType({k: tuple(v) if isinstance(v, list) else v for k, v in sentences.items()})


def kept(value, written, units: Units | None = None):
    """The sentence (or list of them) as written where `value` is it, or its API wording (the
    face's `speak`); else `value` itself: a field set anew since (dataclasses.replace) wins."""
    if written is None or written is value:
        return value
    from levitron.runtime.words import render

    def same(w, v) -> bool:
        return w == v or render(w, "api", units) == v
    if isinstance(written, (list, tuple)):
        vs = list(value) if value is not None else None
        return written if vs is not None and len(vs) == len(written) and all(map(same, written, vs)) else value
    return written if same(written, value) else value


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _one(value: float, unit: str, units: Units) -> str:
    if unit == "m":
        return units.length(value)
    if unit == "kg":
        return units.mass(value)
    return units.value(value, unit, 6)


def _quantity(value: str, unit: str, units: Units) -> str:
    value = value.strip()
    if not value:
        return units.named(unit)
    v = _number(value)
    if v is not None:
        if units.si and unit not in ("m", "kg"):
            return f"{value} {unit}"               # as written: the runtime chose its digits
        return _one(v, unit, units)
    inner = value[1:-1] if value[:1] == "[" and value[-1:] == "]" else None
    parts = [_number(p) for p in (inner if inner is not None else value).split(",")]
    if any(p is None for p in parts):
        return f"{value} {units.unit(unit)}".rstrip()
    if inner is not None and len(parts) == 2:
        lo, hi = parts
        if unit == "m":
            return units.length_span(lo, hi)
        if unit == "kg":
            return span(lo, hi, units.mass)
        return f"{value} {units.unit(unit)}".rstrip()
    return ", ".join(_one(p, unit, units) for p in parts)


def shown(text, units: Units | None) -> str:
    """`text` with every quantity marker in `units`' display units (None: an SI scene's)."""
    if not text:
        return ""
    text = str(text)
    u = units if units is not None else Units(si=True)
    return QUANTITY.sub(lambda m: _quantity(m.group(1), m.group(2), u), text) if "‹" in text else text
