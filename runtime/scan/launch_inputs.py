"""What a launch varies (runtime/scan/launch_odds.py samples them): the hand's inputs (spin, tilt,
its azimuth, offset, velocity, mass, strength, temperature) and the apparatus's imperfections, each
an `Apparatus` entry that sets a runtime parameter of the model (a base that is not level, a magnet
off its axis), with the unit of each input's JSON numbers. Another imperfection with a runtime
parameter is one entry of APPARATUS. Beside them what an input means for the top: the magnets'
strength at a temperature (`temperature_factor`) and whether a spin can float the success time at
all (`reach_warnings`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from levitron.scene.keys import KEY_BOUNDS, LAUNCH_KEYS, Bound
from levitron.runtime.errors import UserError
from levitron.runtime.scan.spreads import Dist, check_support, spec_text

INPUTS = ("spin", "tilt", "tilt_azimuth", "offset", "velocity", "mass", "strength", "temperature")


@dataclass(frozen=True)
class Apparatus:
    """An imperfection of the apparatus sampled like a launch input (module docstring): each sample
    sets the runtime parameter `param`, which a model has only where the scene declares `scene_key`
    (scene/keys.py TILT_PARAMS). `moves`: a value other than 0 moves the equilibrium off the
    launch point (so launches with no tilt, offset or velocity still test something). `default`:
    the distribution when none is given, from the model (None: the model's own value, fixed)."""
    name: str
    param: str
    unit: str
    scene_key: str
    moves: bool
    default_text: str
    default: object = None
    direction_of: str | None = None     # the input whose direction this is: moot where that is fixed at 0


def _downhill_default(model):
    """Over an axially symmetric plate the downhill direction matters only relative to the launch's
    own directions (offset along x, velocity along y, the tilt's azimuth): unknown to the person, so
    uniform over the turn. Over a rectangle the plate's sides fix directions: the scene's own."""
    from levitron.runtime.physics.stability import symmetry
    if symmetry(model.scene.data["plate"], model.pvals()).name == "axial":
        return Dist("uniform", 0.0, 2 * math.pi)
    return Dist("fixed", float(model.pvals()["base_tilt_azimuth"]))


# the apparatus inputs: another imperfection with a runtime parameter is one entry here
APPARATUS = (
    Apparatus("base_tilt", "base_tilt", "rad", "plate.tilt", True, "the scene's plate.tilt (0: level)"),
    Apparatus("base_tilt_azimuth", "base_tilt_azimuth", "rad", "plate.tilt", False,
              "uniform:0,2pi rad over an axially symmetric plate, else the scene's plate.tilt_azimuth; "
              "the scene's where the base tilt is fixed at 0", _downhill_default, "base_tilt"),
    Apparatus("moment_tilt", "moment_tilt", "rad", "top.moment_tilt", True,
              "the scene's top.moment_tilt (0: the magnet on the axis)"),
)
ALL_INPUTS = INPUTS + tuple(a.name for a in APPARATUS)
# the [launch] table takes every input a flag takes: its keys (scene/keys.py LAUNCH_KEYS) are checked
# here, at import, so an input added above without its table key fails at once, not in a user's scene
_UNTABLED = set(ALL_INPUTS) - {k.name for k in LAUNCH_KEYS}
if _UNTABLED:
    raise ImportError(f"launch inputs without a [launch] key in scene/keys.py LAUNCH_KEYS: {sorted(_UNTABLED)}")
# what each input's numbers are (the module docstring): the SI unit of its JSON numbers, "1" for a
# relative deviation d (mass m (1 + d), strength mu (1 + d)), "degC" for the temperature
INPUT_UNITS = {"spin": "rad/s", "tilt": "rad", "tilt_azimuth": "rad", "offset": "m", "velocity": "m/s",
               "mass": "1", "strength": "1", "temperature": "degC", **{a.name: a.unit for a in APPARATUS}}


# the bounds a spread's whole support is held to, each the bound of the scene key the input stands
# for (scene/keys.py KEY_BOUNDS: `--set plate.tilt=1.6` and `--base-tilt uniform:0,1.6` are refused
# alike); mass and strength are relative deviations d of a quantity that must stay positive
_POSITIVE = Bound(-1.0, math.inf, lo_open=True, text="a deviation > -100 %")
INPUT_BOUNDS = {
    "base_tilt": KEY_BOUNDS["plate.tilt"].mirrored("|base_tilt| < pi/2 (plate.tilt's bound: a negative "
                                                   "tilt is the same tilt downhill the other way)"),
    "moment_tilt": KEY_BOUNDS["top.moment_tilt"],
    "mass": _POSITIVE,
    "strength": _POSITIVE,
}


def check_bounds(dists: dict, given) -> None:
    """Every input's spread against its bound (INPUT_BOUNDS), quoting it as given (the defaults as
    spec_text): one place for the flags, the [launch] table and the API's inputs."""
    for name, bound in INPUT_BOUNDS.items():
        if name in dists:
            typed = given[name] if name in given else spec_text(name, dists[name])
            what = f" (it makes the {name} non-positive)" if bound is _POSITIVE else ""
            check_support(name, dists[name], typed, bound, INPUT_UNITS[name], what)


def apparatus_of(model) -> tuple[Apparatus, ...]:
    """The apparatus inputs this model has the terms of (the others it cannot sample)."""
    return tuple(a for a in APPARATUS if a.param in model.param_names)


def refuse_apparatus(model, given) -> None:
    """A one-line UserError for an apparatus input given to a model without its term."""
    have = {a.name for a in apparatus_of(model)}
    for a in APPARATUS:
        if a.name in given and a.name not in have:
            raise UserError(f"launch {a.name}: scene '{model.scene.name}' has no {a.scene_key}, so its "
                            f"model has no {a.param} to sample; pass «set» {a.scene_key}=0 (or put "
                            f"{a.scene_key} in the scene) and the launches set it")


def temperature_factor(model, T: float) -> float:
    """The factor on mu at temperature T relative to the scene's own (scene/load.py's linear
    model of both magnets' remanence)."""
    from levitron.scene.keys import T_REF
    data = model.scene.data
    ap = float(data["plate"].get("temperature_coefficient", 0.0))
    at = float(data["top"].get("temperature_coefficient", 0.0))
    T0 = float(data.get("temperature", T_REF))
    f = (1 + ap * (T - T_REF)) * (1 + at * (T - T_REF))
    return f / ((1 + ap * (T0 - T_REF)) * (1 + at * (T0 - T_REF)))


def centre(d: Dist) -> float:
    """The middle of a distribution: the mean, the middle of a uniform range, the fixed value."""
    return 0.5 * (d.a + d.b) if d.kind == "uniform" else d.a


def reach_warnings(model, spin: Dist, interval, tau, success_time: float, defaulted: bool) -> list[str]:
    """In air: a one-line warning when a launch at the spin's centre cannot float the success time
    at all by the adiabatic prediction, tau ln(omega_0 / sigma_lo) < success_time (runtime/physics/
    friction.py: the spin decays as exp(-t/tau) and the top falls where it crosses sigma_lo), so
    that the odds say more of the spin asked for than of the top (the default spin once flew
    88 s against a default success time of 100 s). [] without air or without a spin interval."""
    from levitron.runtime.physics.friction import crossing_time
    from levitron.runtime.ui.human import Units
    if tau is None or not interval:
        return []
    w0 = centre(spin)
    t = crossing_time(w0, interval[0], 1 / tau)
    if t is None or t >= success_time:
        return []
    u = Units.of_scene(model.scene)
    which = "the default spin" if defaulted else "the spin's centre"
    return [f"{which} {u.rate(w0).split(' (')[0]} floats only about {u.time(t)} by the adiabatic prediction "
            f"tau ln(omega_0 / sigma_lo), less than the success time {u.time(success_time)}: even a steady "
            "launch at it cannot succeed; launch faster («spin») or ask for a shorter flight («success_time»)"]


def resonance_warnings(model, res, spin: Dist, tau, success_time: float) -> list[str]:
    """A one-line warning where the hand's spins (the central 95 % of its distribution) include an
    explosive three-wave resonance inside the window (runtime/physics/resonances.py,
    docs/resonances.md), or in air pass one while they slow down over the success time (the spin
    decays as exp(-t/tau), runtime/physics/friction.py): near it a launch tolerates less tilt
    (`stability --tilt-tolerance`). [] where none is crossed or the resonances are not computed
    (no window, the top off the axis). res: the StabilityResult of the scene's top."""
    from levitron.runtime.physics.stability_answer import resonances_of
    from levitron.runtime.words import si
    found = resonances_of(model, res) or ()
    lo, hi = ((spin.a - 2 * spin.b, spin.a + 2 * spin.b) if spin.kind == "normal" else
              (spin.a, spin.b) if spin.kind == "uniform" else (spin.a, spin.a))
    slowest = lo * math.exp(-success_time / tau) if tau else lo
    hits = [r for r in found if r.order == 3 and r.explosive and min(lo, slowest) <= r.spin <= hi]
    if not hits:
        return []
    r = hits[0]
    how = ("include" if lo <= r.spin else f"pass, slowing down over {si(success_time, 's')} of flight,")
    return [f"the hand's spins, {si(lo, 'rad/s')} to {si(hi, 'rad/s')}, {how} the explosive resonance at "
            f"{si(r.spin, 'rad/s')} ({r.relation}), where a launch tolerates less tilt "
            f"(`«levitron=stability» «tilt_tolerance»`): launch away from it or with less wobble"]
