"""What a launch varies (runtime/scan/launch_odds.py samples them): the hand's inputs (spin, tilt,
its azimuth, offset, velocity, mass, strength, temperature) and the apparatus's imperfections, each
an `Apparatus` entry that sets a runtime parameter of the model (a base that is not level, a magnet
off its axis), with the unit of each input's JSON numbers. Another imperfection with a runtime
parameter is one entry of APPARATUS. Beside them what an input means for the top: the magnets'
strength at a temperature (`temperature_factor`), whether a spin can float the success time at
all (`reach_warnings`) and whether the model's field holds as far off the axis as the launches
take the top (`field_order_warnings`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

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
    from levitron.runtime.physics.stability.analysis import symmetry
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


def check_decay_horizon(model, z_s: float, spin: Dist, tau, defaulted: bool) -> None:
    """No verdict without the physics to support it: where the success time is the default tau / 2
    (in air) and shorter than one period of the slowest motion at the spin's centre (runtime/
    simulate/start.py slow_period), no launch can show in it whether the top floats (a spin decay
    time far below the motion's time scale), so the Monte Carlo is refused in one line rather than
    counting every launch a success."""
    if tau is None or not defaulted or not spin.a > 0:
        return
    from levitron.runtime.simulate.start import slow_period
    from levitron.runtime.words import si
    slow = slow_period(model, model.param("m"), z_s, float(spin.a))
    if 0.5 * tau < slow:
        shown = si(slow, "s", ".3g")
        raise UserError(f"the spin decay time {si(tau, 's')} gives a default success time of {si(0.5 * tau, 's')}, "
                        f"shorter than one period of the top's slowest motion ({shown}): no launch can show in it "
                        f"whether the top floats; give «success_time» (at least {shown}) or check the "
                        "scene's spin_decay_time", param="success_time", value=0.5 * tau, unit="s")


def reach_warnings(model, spin: Dist, interval, tau, success_time: float, defaulted: bool) -> list[str]:
    """In air: a one-line warning when a launch at the spin's centre cannot float the success time
    at all by the adiabatic prediction, tau ln(omega_0 / sigma_lo) < success_time (runtime/physics/
    apparatus/friction.py: the spin decays as exp(-t/tau) and the top falls where it crosses sigma_lo), so
    that the odds say more of the spin asked for than of the top (the default spin once flew
    88 s against a default success time of 100 s). [] without air or without a spin interval."""
    from levitron.runtime.physics.apparatus.friction import crossing_time
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
    explosive three-wave resonance inside the window (runtime/physics/stability/resonances.py,
    docs/resonances.md), or in air pass one while they slow down over the success time (the spin
    decays as exp(-t/tau), runtime/physics/apparatus/friction.py): near it a launch tolerates less tilt
    (`stability --tilt-tolerance`). [] where none is crossed or the resonances are not computed
    (no window, the top off the axis). res: the StabilityResult of the scene's top."""
    from levitron.runtime.physics.stability.answer import resonances_of
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


FIELD_SDS = 3.0       # a normal spread reaches this many sd from its mean


def _far(d: Dist | None) -> float:
    """How far from 0 a spread reaches: its far end (a normal one's FIELD_SDS sd from the mean)."""
    if d is None:
        return 0.0
    if d.kind == "normal":
        return abs(d.a) + FIELD_SDS * d.b
    return max(abs(d.a), abs(d.b)) if d.kind == "uniform" else abs(d.a)


def field_reach(model, dists: dict, z_s: float) -> float:
    """How far off the axis (m) the launches take the top, a sum of reaches: the offset's far end
    (normal: 3 sd), the tilt's (the launch's plus the magnet's on its axis) 2 theta |Phi_1/Phi_2|,
    where the field's own tilt B_r/B_z = r Phi_2 / (2 Phi_1) is theta (thesis eq. 2.2.6: a top whose
    axis follows the field sits there), and the base's tilt m g beta / k_r, with k_r = |mu|
    (Phi_2^2/4 - Phi_1 Phi_3/2) / |Phi_1| the sideways stiffness of |mu| |B| on the axis (the
    linear shift of runtime/physics/apparatus/tilted_equilibrium.py). The velocity's reach is left out."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    P = model.pvals()
    _, f1, f2, f3 = (float(v) for v in eqm.model_onaxis(model, model.p)(z_s)[:4])
    tilt = _far(dists.get("tilt")) + _far(dists.get("moment_tilt"))
    k_r = abs(P["mu"]) * (0.25 * f2 * f2 - 0.5 * f1 * f3) / abs(f1)
    base = P["m"] * P["g"] * math.sin(min(_far(dists.get("base_tilt")), 1.0)) / k_r if k_r > 0 else 0.0
    return _far(dists.get("offset")) + (2 * tilt * abs(f1 / f2) if f2 else 0.0) + base


def field_differences(field, reference, r: float, z: float, azimuths: int = 8) -> dict[str, float]:
    """The largest relative differences, over `azimuths` points at radius r and height z, between
    two fields (points (N, 3) -> B (N, 3)): of B, of its gradient (the 3x3 dB_i/dx_j, Frobenius
    norm) and of the sideways pull d|B|/dr (the force on a top whose magnet follows the field,
    -|mu| grad |B|, across the axis: what holds it there), by central differences of 1e-4 z."""
    h = 1e-4 * z
    out = {"field": 0.0, "gradient": 0.0, "pull": 0.0}
    for a in np.arange(azimuths) * 2 * math.pi / azimuths:
        e_r = np.array([math.cos(a), math.sin(a), 0.0])
        c = r * e_r + [0.0, 0.0, z]
        pts = np.array([c] + [c + s * h * e for e in (*np.eye(3), e_r) for s in (1, -1)])
        got = [np.asarray(f(pts), float).reshape(len(pts), 3) for f in (field, reference)]
        grads = [np.array([(B[1 + 2 * i] - B[2 + 2 * i]) / (2 * h) for i in range(3)]) for B in got]
        pulls = [(np.linalg.norm(B[7]) - np.linalg.norm(B[8])) / (2 * h) for B in got]
        for key, (x, y) in {"field": (got[0][0], got[1][0]), "gradient": grads, "pull": pulls}.items():
            size = float(np.linalg.norm(y))
            if size > 0:
                out[key] = max(out[key], float(np.linalg.norm(np.subtract(x, y))) / size)
    return out


def field_order_warnings(model, dists: dict, z_s: float) -> list[str]:
    """A one-line warning where the launches take the top so far off the axis (`field_reach`) that the
    model's field there, the expansion about the axis cut at its field.order (thesis eqs. 2.2.4-2.2.7),
    differs from the exact field (runtime/physics/plates, where the plate kind has a closed form; else
    from the next even order's model, derived once into the cache: 8-20 s the first time) by more
    than 1 % in the field, its gradient or its sideways pull (`field_differences`): the odds lean on
    it; the warning names the «set» that raises the order. [] where the model's field is exact (a
    plain rectangle) or agrees. A check of the field, not of the odds: milliseconds with a closed form."""
    from levitron.runtime.physics.plates import plate_field
    from levitron.runtime.physics.field.truncation import RTOL, SCENE_MAX_ORDER, expanded, loader
    from levitron.runtime.words import si
    scene, n = model.scene, int(model.manifest.field_order)
    if not expanded(scene.data["plate"]):
        return []
    r = field_reach(model, dists, z_s)
    if not r > 0:
        return []
    exact = plate_field(scene.data["plate"], scene.params, np.array([[r, 0.0, z_s]]))
    if exact is not None and np.all(np.isfinite(exact)):
        against, reference = "the exact field", (lambda pts: plate_field(scene.data["plate"], scene.params, pts))
    else:
        if n + 2 > SCENE_MAX_ORDER:
            return []
        try:
            higher = loader(model)(n + 2)
        except UserError:
            return []
        against, reference = f"order {n + 2}'s", (lambda pts: np.array([higher.field(q) for q in pts]))
    d = field_differences(lambda pts: np.array([model.field(q) for q in pts]), reference, r, z_s)
    if max(d.values()) <= RTOL:
        return []
    fix = (f"derive a higher order: the scene key field.order = {n + 2}" if n + 2 <= SCENE_MAX_ORDER else
           f"no scene takes an order above {SCENE_MAX_ORDER}: launch closer to the axis")
    return [f"the launches reach {si(r, 'm', '.3g')} off the axis (3 sd of the offset, the tilts' and the "
            f"base's reach), where the model's field (the expansion about the axis cut at order {n}, thesis "
            f"eq. 2.2.6) differs from {against} by {d['field'] * 100:.2g} %, its gradient by "
            f"{d['gradient'] * 100:.2g} % and its sideways pull d|B|/dr by {d['pull'] * 100:.2g} %: the odds "
            f"lean on it; {fix}"]
