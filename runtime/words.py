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
"""
from __future__ import annotations

import dataclasses
import re
import sys

__all__ = ["FACES", "MARKER", "render", "setting", "speak"]

FACES = ("cli", "api")

# the names whose API keyword is not the name itself
_API_NAME = {"set": "overrides", "temperature_spread": "inputs['temperature']"}
# the commands a sentence sends a person to, as the Study methods that answer the same
_API_METHOD = {"equilibrium": "Study.equilibria()", "stability": "Study.stability()",
               "simulate": "Study.simulate()", "scan": "Study.scan()", "launch": "Study.launch()",
               "optimize": "Study.optimize()", "trim": "Study.trim()"}

MARKER = re.compile(r"«([a-z][a-z0-9_]*)(?:=([^«»]+))?»")
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


_WORDING = {"cli": _cli, "api": _api}


def render(text, face: str):
    """`text` with each marker worded for `face` ("cli" or "api"); anything not text as it is."""
    if not isinstance(text, str) or "«" not in text:
        return text
    word = _WORDING[face]
    return MARKER.sub(lambda m: word(m.group(1), m.group(2)), text)


def speak(answer, face: str):
    """`answer` with every sentence in it worded for `face`: text, and the text inside dicts,
    lists, tuples, object arrays and dataclasses (a new one where anything changed: an answer
    without a marker comes back as the same object, so the API pays only the walk); numbers,
    numeric arrays and other objects as they are."""
    if isinstance(answer, str):
        return render(answer, face)
    if answer is None or type(answer) in (bool, int, float):
        return answer
    if type(answer) is dict:
        new = {k: speak(v, face) for k, v in answer.items()}
        return answer if all(new[k] is v for k, v in answer.items()) else new
    if type(answer) in (list, tuple):
        new = [speak(v, face) for v in answer]
        return answer if all(a is b for a, b in zip(new, answer)) else type(answer)(new)
    np = sys.modules.get("numpy")      # no array without NumPy: --version and --help start without it
    if np is not None and isinstance(answer, (np.ndarray, np.generic)):
        if answer.dtype != object:
            return answer
        new = [speak(v, face) for v in answer.flat]
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
                new = speak(v, face)
                if new is not v:
                    changes[f.name] = new
        return dataclasses.replace(answer, **changes) if changes else answer
    return answer
