"""The API's arguments checked the way a scientist passes them.

* numbers: any real number, NumPy scalars included (`np.float64(0.0362)`, `np.int64(3)`, a 0-d
  array), so that `for m in np.linspace(...)` works; bools and text are not numbers;
* names: a list (or tuple) of strings, never one string taken character by character;
* unknown names: refused with the valid ones listed (a scene's numeric keys, the quantities of
  `Study.gradient`, the options of `Study.simulate`).

Errors are runtime.errors.UserError (exported as levitron.UserError), one line, in the API's
words.
"""
from __future__ import annotations

import difflib
import numbers
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from levitron.runtime.errors import UserError

__all__ = ["UserError", "Named", "bind", "boxes", "choice", "launch_values", "names", "number", "options", "plain",
           "real_column", "real_columns", "scene_keys", "units_allowed", "varies"]


def is_number(value) -> bool:
    """A real number (Python or NumPy, a 0-d array included), not a bool."""
    if isinstance(value, (bool, np.bool_)):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and np.issubdtype(value.dtype, np.number) and not np.iscomplexobj(value)
    return isinstance(value, numbers.Real)


def number(value, what: str) -> float:
    """`value` as a float; UserError naming `what` if it is no real number. A setting with a unit
    (scene/quantity.py SETTING_UNITS) also takes one number with a unit: spin="30 Hz" is 2 pi 30."""
    from levitron.scene import quantity
    if quantity.has_unit(value) and what in quantity.SETTING_UNITS:
        try:
            return quantity.setting_value(value, what)
        except quantity.SceneError as exc:
            raise UserError(str(exc)) from None
    if not is_number(value):
        raise UserError(f"{what} = {value!r} is not a number: pass a float (NumPy scalars are fine)")
    return float(value)


def real_column(value, what: str):
    """`value` (a number or an array) as given, refused if it is complex: NumPy would drop its
    imaginary part with a warning. NaN and inf are refused where the numbers are read
    (runtime/scan/batch.py, Study._grid)."""
    if isinstance(value, (str, bytes)) or not np.iscomplexobj(value):
        return value
    a = np.ravel(np.asarray(value))
    first = complex(a[np.flatnonzero(np.imag(a))[0]] if np.any(np.imag(a)) else a[0])
    raise UserError(f"{what} has the complex value {first}: pass real numbers (NumPy would drop the "
                    "imaginary part); take np.real(...) if it is zero")


def real_columns(columns: Mapping) -> None:
    """real_column of every {name: number or array} (simulate_many's spin, tilt, ... and scene values)."""
    for name, value in columns.items():
        real_column(value, name)


def launch_values(values, columns: Mapping) -> Mapping:
    """simulate_many's `values` ({scene key: number or array}) once checked to be a mapping, and
    every launch column (`columns`: spin, tilt, ...) and value real (real_columns)."""
    if not isinstance(values, Mapping):
        raise UserError("values must be a mapping of scene key -> number or array, e.g. "
                        "{'top.mass': [0.051, 0.052]}")
    real_columns({**columns, **values})
    return values


def units_allowed(si: bool, values) -> None:
    """A number typed with a unit ("30 Hz", scene/quantity.py) is refused in a dimensionless scene."""
    from levitron.scene.quantity import has_unit
    typed = next((v for v in values if has_unit(v)), None) if not si else None
    if typed is not None:
        raise UserError(f"{typed!r}: this scene is dimensionless: give the number in the scene's own units, "
                        "without a unit")


def plain(value):
    """A NumPy number as the Python float or int it is (for the TOML writer); anything else as is."""
    if is_number(value) and not isinstance(value, (bool, np.bool_)):
        return int(value) if isinstance(value, (numbers.Integral, np.integer)) else float(value)
    return value


def names(value, what: str, valid: Iterable[str] | None = None, each: str | None = None) -> list[str]:
    """A list of names: refuses one string (it would be taken letter by letter) and, with
    `valid`, any name not in it, listing the valid ones (`each`: what one name is, e.g. "scene
    key" for the list `keys`)."""
    if isinstance(value, str):
        raise UserError(f"{what} must be a list of names, not the string {value!r}: write [{value!r}]")
    try:
        out = list(value)
    except TypeError:
        raise UserError(f"{what} must be a list of names, not {value!r}") from None
    for name in out:
        if not isinstance(name, str):
            raise UserError(f"{what}: {name!r} is not a name (a string)")
        if valid is not None:
            choice(name, each or what, valid)
    return out


def choice(name, what: str, valid: Iterable[str]) -> str:
    """`name` if it is one of `valid`, else a UserError listing them."""
    valid = list(valid)
    if name not in valid:
        near = difflib.get_close_matches(str(name), valid, n=1) if isinstance(name, str) else []
        hint = f"did you mean {near[0]!r}? " if near else ""
        raise UserError(f"{what} {name!r} is unknown: {hint}use one of {', '.join(valid)}")
    return name


def bind(fn, args, kwargs, what: str, unknown=None) -> None:
    """Check a call's arguments against `fn`'s signature: an unknown keyword, a missing argument or
    a wrong number of arguments is a one-line UserError ("Study.keys: argument 'colour' is unknown:
    use one of ...", "Study.simulate: the argument spin is missing: ..."), not Python's TypeError.
    unknown(name): the method's own refusal of a keyword it does not take (raises UserError); a
    function with **kwargs takes any keyword."""
    import inspect
    sig = inspect.signature(fn)
    params = sig.parameters
    names = [n for n, p in params.items() if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) and n != "self"]
    if not any(p.kind is p.VAR_KEYWORD for p in params.values()):
        for k in kwargs:
            if k not in params or params[k].kind is inspect.Parameter.POSITIONAL_ONLY:
                if unknown is not None:
                    unknown(k)          # raises in the method's words
                if not names:
                    raise UserError(f"{what}: argument {k!r} is unknown: {what}() takes no argument")
                choice(k, f"{what}: argument", names)
    try:
        bound = sig.bind_partial(*args, **kwargs)
    except TypeError as exc:
        raise UserError(f"{what}: {exc}; its arguments are {', '.join(names)}") from None
    required = [n for n in names if params[n].default is params[n].empty]
    missing = [n for n in required if n not in bound.arguments]
    if missing:
        raise UserError(f"{what}: the argument {' and '.join(missing)} {'is' if len(missing) == 1 else 'are'} "
                        f"missing: call {what}({', '.join(required)}, ...); its arguments are {', '.join(names)}")


class Named(dict):
    """A dict of named things (Study.functions) whose unknown name is a one-line UserError listing
    the names, not a bare KeyError; `absent(name)`: the sentence for a name the scene could have
    but does not (e.g. a part it did not derive), else None."""

    def __init__(self, what: str, items, absent=None):
        super().__init__(items)
        self.what, self.absent = what, absent

    def __missing__(self, name):
        why = self.absent(name) if self.absent is not None and isinstance(name, str) else None
        if why:
            raise UserError(why)
        choice(name, self.what, self)


def scene_keys(data: Mapping, prefix: str = "") -> list[str]:
    """The scene's numeric keys in `section.key` form (compound parts as plate.parts.<i>.<key>),
    for error messages."""
    out = []
    for k, v in data.items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping):
            out += scene_keys(v, key + ".")
        elif isinstance(v, list):
            for i, item in enumerate(v):
                if isinstance(item, Mapping):
                    out += scene_keys(item, f"{key}.{i}.")
        elif is_number(v):
            out.append(key)
    return out


def boxes(vary: Mapping, what: str = "vary") -> dict[str, tuple[float, float]]:
    """{key: (lo, hi)} with numbers (NumPy's too) and lo < hi; a UserError otherwise."""
    if not isinstance(vary, Mapping):
        raise UserError(f"{what} must be a dict {{key: (lo, hi)}}, not {vary!r}")
    out = {}
    for key, box in vary.items():
        if isinstance(box, str) or not hasattr(box, "__len__") or len(box) != 2:
            raise UserError(f"{what}[{key!r}] = {box!r}: give a pair (lo, hi)")
        lo, hi = number(box[0], f"{what}[{key!r}] lo"), number(box[1], f"{what}[{key!r}] hi")
        out[key] = (lo, hi)
    return out


def varies(vary) -> list:
    """{scene key: (lo, hi)} as runtime/design/scene_keys.py Vary boxes, checked (the CLI's --vary
    KEY=LO:HI reads the same)."""
    from levitron.runtime.design.scene_keys import Vary
    if not isinstance(vary, Mapping) or not vary:
        raise UserError("vary: give a non-empty mapping of scene key -> (lo, hi), e.g. "
                        "{'top.mass': (0.05, 0.052)}")
    return [Vary.checked(key, lo, hi, f"vary {key!r}: {(lo, hi)!r}") for key, (lo, hi) in boxes(vary).items()]


def options(given: dict, valid: Sequence[str], aliases: Mapping[str, str], what: str,
            numbers: Sequence[str]) -> dict:
    """A method's options with the command line's names (`aliases`: tilt_azimuth, step) taken as
    theirs, unknown names refused with the valid ones listed, `numbers` checked as numbers."""
    for alias, name in aliases.items():
        if alias in given:
            if name in given:
                raise UserError(f"pass {alias} or {name}, not both (the same option)")
            given[name] = given.pop(alias)
    for name in given:
        choice(name, what, [*valid, *aliases])
    for name in numbers:
        if given.get(name) is not None:
            given[name] = number(given[name], name)
    return given
