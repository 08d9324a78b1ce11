"""How a runtime sentence names what a person sets, so that each face words it its own way.

The numerics do not know whether a command line, the Python API or the report asked them. A
sentence that tells the person what to change names the setting by a marker, the setting's name
between guillemets (the API's keyword name, as `Study` takes it):

    "pass e.g. «t_end=1»"          command line: "pass e.g. --t-end 1"   API: "pass e.g. t_end=1"
    "raise «t_end» or lower «step»" command line: "raise --t-end or ..."  API: "raise t_end or ..."
    "«integrator=rk4»"             command line: "--integrator rk4"      API: "integrator='rk4'"
    "«set=top.mass=0.05»"          command line: "--set top.mass=0.05"   API: "overrides={'top.mass': 0.05}"
    "`«levitron=equilibrium»`"     command line: "`levitron equilibrium`" API: "`Study.equilibria()`"

A value inside a marker is the developer's example or a number the code formats; `setting(name,
text)` writes one and leaves a text that would break the marker beside it. What the user typed
(a path, a spec) stays outside: "«fit» {path}". `render(text, face)` words a sentence for a face, `speak(answer,
face)` every sentence of an answer (a dataclass, dict, list or object array of them). A marker
that does not parse is left as it is; tests/house/test_words.py checks that every marker in the
runtime's source names an option of the command line and that no sentence below cli/ spells a
flag itself.

A number with an SI unit is a quantity marker, written by `si(value, unit)` ("‹0.157391|m›"; a
unit named alone, "a length in ‹|m›", by `si_unit(unit)`), and shown in the units of the scene
a face passes (runtime/ui/human.py Units): "0.157391 m" in an SI scene and wherever no scene is
known (the JSON's SI), "0.157391" in a dimensionless one, whose rates are "rad/time" and times
"time units". A wall time (the computer's seconds) is plain text, never a quantity.
"""
from __future__ import annotations

import dataclasses
import re
import sys

__all__ = ["FACES", "MARKER", "QUANTITY", "in_units", "render", "setting", "si", "si_span", "si_unit", "speak"]

FACES = ("cli", "api")

# the names whose API keyword is not the name itself
_API_NAME = {"set": "overrides", "temperature_spread": "inputs['temperature']"}
# the commands a sentence sends a person to, as the Study methods that answer the same
_API_METHOD = {"equilibrium": "Study.equilibria()", "stability": "Study.stability()",
               "simulate": "Study.simulate()", "scan": "Study.scan()", "launch": "Study.launch()",
               "optimize": "Study.optimize()", "trim": "Study.trim()"}

MARKER = re.compile(r"«([a-z][a-z0-9_]*)(?:=([^«»]+))?»")
QUANTITY = re.compile(r"‹([^‹›|]*)\|([^‹›|]+)›")
_NUMBER = re.compile(r"-?(?:\d[\w.+-]*|\.\d[\w.+-]*)(?::[\w.+-]+)*")


def _cli(name: str, value: str | None) -> str:
    if name == "levitron":
        return f"levitron {value}"
    flag = "--" + name.replace("_", "-")
    return flag if value is None else f"{flag} {value}"


def _api(name: str, value: str | None) -> str:
    if name == "levitron":
        return _API_METHOD.get(value, f"levitron {value}")
    word = _API_NAME.get(name, name)
    if value is None:
        return word
    if name == "set" and "=" in value:
        key, _, v = value.partition("=")
        return f"{word}={{{key!r}: {v if _NUMBER.fullmatch(v) else repr(v)}}}"
    literal = _NUMBER.fullmatch(value) or value in ("True", "False", "None") or value[:1] in "'\"[({"
    return f"{word}={value if literal else repr(value)}"


def setting(name: str, text: str) -> str:
    """The marker of setting `name` with the value `text` ("«seed=-1»"), or "«name» text" where
    the text holds a guillemet of its own."""
    return f"«{name}» {text}" if "«" in text or "»" in text else f"«{name}={text}»"


def si(value, unit: str, fmt: str = ".6g") -> str:
    """The quantity marker of `value` (a number, formatted by `fmt`; or a text such as a span
    "[0.1, 0.2]") in the SI unit `unit`."""
    text = value if isinstance(value, str) else f"{value:{fmt}}"
    return f"‹{text}|{unit}›"


def si_span(lo: float, hi: float, unit: str) -> str:
    """The quantity marker of the interval [lo, hi] in the SI unit `unit`."""
    return si(f"[{lo:.6g}, {hi:.6g}]", unit)


def si_unit(unit: str) -> str:
    """The quantity marker of the SI unit `unit` named alone ("a length in ‹|m›")."""
    return f"‹|{unit}›"


def _shown(m, units) -> str:
    value, unit = m.group(1), m.group(2)
    if not value:
        return unit if units is None else units.named(unit)
    return f"{value} {unit if units is None else units.unit(unit)}".rstrip()


_WORDING = {"cli": _cli, "api": _api}


def render(text, face: str, units=None):
    """`text` with each marker worded for `face` ("cli" or "api") and each quantity in `units`
    (a Units; None: SI); anything not text as it is."""
    if not isinstance(text, str) or ("«" not in text and "‹" not in text):
        return text
    word = _WORDING[face]
    return in_units(MARKER.sub(lambda m: word(m.group(1), m.group(2)), text), units)


def in_units(text: str, units=None) -> str:
    """`text` with each quantity marker shown in `units` (None: SI), its settings as they are."""
    return QUANTITY.sub(lambda m: _shown(m, units), text) if "‹" in text else text


def speak(answer, face: str, units=None):
    """`answer` with every sentence in it worded for `face`: text, and the text inside dicts,
    lists, tuples, object arrays and dataclasses (a new one where anything changed: an answer
    without a marker comes back as the same object, so the API pays only the walk); numbers,
    numeric arrays and other objects as they are."""
    if isinstance(answer, str):
        return render(answer, face, units)
    if answer is None or type(answer) in (bool, int, float):
        return answer
    if type(answer) is dict:
        new = {k: speak(v, face, units) for k, v in answer.items()}
        return answer if all(new[k] is v for k, v in answer.items()) else new
    if type(answer) in (list, tuple):
        new = [speak(v, face, units) for v in answer]
        return answer if all(a is b for a, b in zip(new, answer)) else type(answer)(new)
    np = sys.modules.get("numpy")      # no array without NumPy: --version and --help start without it
    if np is not None and isinstance(answer, (np.ndarray, np.generic)):
        if answer.dtype != object:
            return answer
        new = [speak(v, face, units) for v in answer.flat]
        if all(a is b for a, b in zip(new, answer.flat)):
            return answer
        out = np.empty(answer.shape, dtype=object)
        out.flat[:] = new
        return out
    if dataclasses.is_dataclass(answer) and not isinstance(answer, type):
        changes = {}
        for f in dataclasses.fields(answer):
            if f.init:
                v = getattr(answer, f.name)
                new = speak(v, face, units)
                if new is not v:
                    changes[f.name] = new
        return dataclasses.replace(answer, **changes) if changes else answer
    return answer
