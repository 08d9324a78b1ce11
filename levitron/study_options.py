"""What every public `Study` method wears (levitron/study.py): its options as keyword parameters
(what an IDE completes and a type checker checks), the call checked against its signature first
(`checked_calls`), and its words and units those of the API (`in_scene_units`).

An option left at None is the command's default, exactly as if it were not passed: `given` keeps the
options passed, and the method hands those on as it always did. An unknown keyword is refused in the
method's own words (`UNKNOWN`: "simulate option 'tend' is unknown: did you mean 't_end'? ...").
`override_texts`: `load`'s overrides as the command line's --set texts.
"""
from __future__ import annotations

import functools
import inspect
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Concatenate, ParamSpec, Protocol, TypeVar

from levitron.scene.checks import SceneError
from levitron.scene.overrides import override_text
from levitron.runtime.errors import UserError
from levitron.runtime.words import render, speak

from . import arguments as arg

if TYPE_CHECKING:
    from levitron.runtime.ui.human import Units

__all__ = ["MANY_OPTIONS", "SIMULATE_ALIASES", "SIMULATE_OPTIONS", "UNKNOWN", "Quantity", "checked_calls", "given",
           "in_scene_units", "override_texts"]

# A number in SI (or the scene's own units in a dimensionless scene), NumPy scalars included, or in an SI
# scene the number with its unit as people type it ("30 Hz", "3 mm": scene/quantity.py)
Quantity = float | str

# Study.simulate's options: runtime.simulate.run.simulate's keywords, and the command line's names
SIMULATE_OPTIONS = ("tilt", "offset", "t_end", "integrator", "tol", "box", "plot", "part", "h",
                    "n_out", "azimuth", "save")
SIMULATE_ALIASES = {"tilt_azimuth": "azimuth", "step": "h"}     # --tilt-azimuth, --step
# Study.simulate_many's: runtime.scan.batch.simulate_many's keywords and `values` (scene keys)
MANY_OPTIONS = ("tilt", "offset", "azimuth", "t_end", "integrator", "tol", "box", "h", "part", "values")
# Study.scan's: runtime.scan.stability_map.scan's keywords
SCAN_OPTIONS = ("t_end", "integrator", "tol", "workers", "scheduler", "base_tilt", "h", "quiet", "engine",
                "scheduler_timeout")


def given(**options: object) -> dict[str, object]:
    """The options passed, by name: those that are not None (None: the command's default)."""
    return {name: value for name, value in options.items() if value is not None}


def override_texts(overrides: Mapping[str, object] | None) -> list[str]:
    """The --set texts of {scene key: value}, written by a TOML writer (scene.overrides.override_text):
    a quote or a newline in a value stays inside it, and the command line's reader reads them.
    Numbers may be NumPy scalars (`for m in np.linspace(...)` works)."""
    if overrides is None:
        return []
    if not isinstance(overrides, Mapping):
        raise UserError(f"overrides must be a mapping of scene key -> value, e.g. {{'top.mass': 0.05}}; "
                        f"got {type(overrides).__name__}")
    try:
        return [override_text(k, arg.plain(v)) for k, v in overrides.items()]
    except SceneError as exc:
        raise UserError(str(exc)) from None


def _launch_option(name: str) -> None:
    from levitron.runtime.scan.launch_odds import LAUNCH_OPTIONS
    raise UserError(f"launch: unknown option {name!r}: use {', '.join(LAUNCH_OPTIONS)}")


def _choice(what: str, valid: tuple[str, ...]) -> Callable[[str], None]:
    def refuse(name: str) -> None:
        arg.choice(name, what, valid)
    return refuse


# how each method refuses a keyword it does not take (others: "Study.keys: argument 'x' is unknown: ...")
UNKNOWN: dict[str, Callable[[str], None]] = {
    "simulate": _choice("simulate option", (*SIMULATE_OPTIONS, *SIMULATE_ALIASES)),
    "simulate_many": _choice("simulate_many option", (*MANY_OPTIONS, *SIMULATE_ALIASES)),
    "scan": _choice("scan option", SCAN_OPTIONS),
    "launch": _launch_option, "trim": _launch_option}


class _HasUnits(Protocol):
    @property
    def units(self) -> Units: ...


S = TypeVar("S", bound=_HasUnits)
P = ParamSpec("P")
R = TypeVar("R")


def in_scene_units(method: Callable[Concatenate[S, P], R]) -> Callable[Concatenate[S, P], R]:
    """A Study method that speaks the API's words and the scene's units: the settings its answer's
    sentences and its UserError name are worded as keyword arguments (runtime/words.py, "api"),
    their quantities shown in the scene's units (as the command's JSON shows them). The UserError
    keeps the setting, value, unit and hint it carried."""
    @functools.wraps(method)
    def wrapper(self: S, /, *args: P.args, **kwargs: P.kwargs) -> R:
        arg.units_allowed(self.units.si, (*args, *kwargs.values()))     # "30 Hz": SI scenes only
        try:
            answer: R = speak(method(self, *args, **kwargs), "api", self.units)
            return answer
        except UserError as exc:
            text = exc.words("api", self.units)
            if text == str(exc):
                raise
            raise UserError(text, param=exc.param, value=exc.value, unit=exc.unit,
                            hint=exc.hint and render(exc.hint, "api", self.units)) from None
    return wrapper


C = TypeVar("C", bound=type)


def checked_calls(cls: C) -> C:
    """Every public method of `cls` checks its call against its signature first (arguments.bind):
    a misspelt keyword, a missing argument or a wrong count of arguments is a one-line UserError,
    not a TypeError."""
    def checked(method: Callable[..., object]) -> Callable[..., object]:
        @functools.wraps(method)
        def wrapper(self: object, *args: object, **kwargs: object) -> object:
            arg.bind(method, (self, *args), kwargs, f"{cls.__name__}.{method.__name__}",
                     UNKNOWN.get(method.__name__))
            return method(self, *args, **kwargs)
        return wrapper
    for name, fn in list(vars(cls).items()):
        if inspect.isfunction(fn) and not name.startswith("_"):
            setattr(cls, name, checked(fn))
    return cls
