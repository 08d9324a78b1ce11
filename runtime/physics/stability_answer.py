"""The answer to "at which spin rates does the top hover stably?": what `levitron stability` prints
and `Study.stability()` returns (thesis 3.3).

`Stability.of(model, height, level_tolerance)` runs the analysis (runtime/physics/stability.py:
the exact route, thesis 3.3.9-3.3.16, and the eigenvalue route beside it; over a tilted base the
equilibrium off the axis, runtime/physics/tilted_stability.py) and, on request, how level the base
(checked against higher orders of the field's expansion, runtime/physics/truncation.py) and how
well aligned the magnet must be; `as_json()` is docs/contract.md's `stability` object,
`plot(path)` draws the spin interval against the base's tilt. SI throughout; `units` says how the
repr and the message show the numbers.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from levitron.runtime.errors import UserError
from levitron.runtime.physics.friction import without_friction
from levitron.runtime.physics.stability import stability_of
from levitron.runtime.physics.stability_result import StabilityResult
from levitron.runtime.ui.human import Units, quantity, restate, sig

_SI = Units(si=True)


@dataclass(frozen=True, repr=False)
class Stability:
    """Linear stability at the hover height: `result` the routes' intervals (StabilityResult; its
    z_s (m), spin_interval (rad/s, None if no spin stabilises: `reason` says why), routes_agree
    (None without a full model), mass (kg: the top analysed; with a height, the one that hovers
    there), equilibrium (over a tilted base: position, axis, offset, ...) are this answer's too);
    stiffness: mu Phi_3(z_s) (N/m, thesis 3.3.3; None over a tilted base); level_tolerance: the
    largest base tilt and moment tilt that keep a stable interval (asked for, else None);
    resonances: the low-order resonances among the linear modes inside the spin interval
    (runtime/physics/resonances.py, docs/resonances.md; strongest first), None where not
    computed (no interval, or the steady motion is off the axis)."""

    result: StabilityResult
    scene: str
    scene_mass: float
    height_given: bool
    eigen_source: str
    stiffness: float | None
    level_tolerance: dict | None = None
    wall_s: float = 0.0
    units: Units = field(default=_SI, compare=False)
    _model: object = field(default=None, compare=False)      # for plot(): at the tolerance's field order
    resonances: tuple | None = None

    @classmethod
    def of(cls, model, height: float | None = None, level_tolerance: bool = False) -> Stability:
        """The analysis of `model`'s top (with `height` (m): the top that hovers there instead)."""
        if level_tolerance and "base_tilt" not in model.param_names:
            raise UserError("«level_tolerance» needs the model of a tilted base: add "
                            "«set=plate.tilt=0» (or the scene's plate.tilt)")
        t0 = time.perf_counter()
        res = stability_of(model, height=height)
        eigen = ("full_jac (generated)" if model.has_function("full_jac") and "p_zeta" in model.part("full").states
                 else "transverse_matrix (8-D)")
        tol, drawn, lines = _level_tolerance(model) if level_tolerance else (None, model, [])
        res.notes.extend(lines)    # a tolerance's field order raised, or a warning
        reso = resonances_of(model, res)
        wall = time.perf_counter() - t0
        # the vertical stiffness U'' = mu Phi_3(z_s) (thesis 3.3.3), N/m: what «constrain»
        # stiffness>=K of `optimize` speaks of; it does not depend on the mass
        k = (model.param("mu") * float(model.onaxis(res.z_s)[3])
             if res.z_s and res.equilibrium is None else None)
        return cls(res, model.scene.name, model.param("m"), height is not None, eigen, k, tol, wall,
                   Units.of_scene(model.scene), drawn, reso)

    # ---- what the result says, as the API has always named it
    @property
    def z_s(self) -> float | None:
        return self.result.z_s

    @property
    def spin_interval(self) -> tuple[float, float] | None:
        iv = self.result.spin_interval
        return None if iv is None else tuple(iv)

    @property
    def reason(self) -> str | None:
        return self.result.reason

    @property
    def routes_agree(self) -> bool | None:
        return self.result.routes_agree

    @property
    def mass(self) -> float | None:
        return self.result.mass

    @property
    def equilibrium(self) -> dict | None:
        return self.result.equilibrium

    @property
    def success(self) -> bool:
        """A spin interval of linear stability exists."""
        return self.spin_interval is not None

    @property
    def message(self) -> str:
        if self.spin_interval is None:
            return f"no stable spin interval: {restate(self.reason, self.units) or 'no stable hover height'}"
        lo, hi = self.spin_interval
        u = self.units
        return f"stable for spin {lo:.6g}-{quantity(u, hi, 'rad/s')} at z_s = {quantity(u, self.z_s, 'm')}" + \
            (f" ({self.reason})" if self.reason else "")

    def __repr__(self) -> str:
        u = self.units
        iv = "None" if self.spin_interval is None else \
            f"{sig(self.spin_interval[0], 6)}-{sig(self.spin_interval[1], 6)} {u.unit('rad/s')}"
        z = "None" if self.z_s is None else quantity(u, self.z_s, "m")
        k = "None" if self.stiffness is None else quantity(u, self.stiffness, "N/m", ".4g")
        return f"Stability(spin_interval={iv}, z_s={z}, stiffness={k}, success={self.success})"

    def as_json(self) -> dict:
        """docs/contract.md's `stability` object (SI)."""
        out = {"scene": self.scene, "mass": self.result.mass, "scene_mass": self.scene_mass,
               "height_given": self.height_given, **self.result.as_dict(), "eigen_source": self.eigen_source}
        if self.level_tolerance is not None:
            out["level_tolerance"] = self.level_tolerance
        out["wall_s"] = self.wall_s
        out["stiffness"] = self.stiffness
        out["resonances"] = None if self.resonances is None else [r.as_json() for r in self.resonances]
        return out

    # ---- actions
    def plot(self, path=None, ax=None):
        """Draw the spin interval against the base's tilt up to the tolerance (runtime/physics/tilt_plot.py)
        into `ax` (an Axes) or a figure of its own, written to `path` (.png, .pdf, .svg) only when
        given one. Returns the matplotlib Figure (the Axes when given `ax`); None where there is no
        tolerance to draw (no stable interval at all)."""
        if self.level_tolerance is None:
            raise UserError("the plot draws the spin interval against the base's tilt: ask for the "
                            "«level_tolerance»")
        if self.level_tolerance["max_base_tilt"] is None:
            return None
        from levitron.runtime.physics.tilt_plot import draw
        model = self._model
        return draw(model, without_friction(model, model.p), self.level_tolerance, path, ax=ax)


def resonances_of(model, res: StabilityResult) -> tuple | None:
    """The resonances inside the spin interval (runtime/physics/resonances.py), strongest first;
    None without an interval or where the steady motion is off the axis (a tilted base, the magnet
    off the axis or off the centre: runtime/physics/modes.py OFF_AXIS)."""
    from levitron.runtime.physics.modes import OFF_AXIS
    if res.spin_interval is None or not res.z_s or res.floquet is not None:
        return None
    p = without_friction(model, model.with_params({"m": res.mass}) if res.mass else model.p)
    P = model.pvals(p)
    if any(P.get(k, 0.0) != 0 for k in OFF_AXIS):
        return None
    from levitron.runtime.physics.resonances import find
    return tuple(find(model, res.z_s, tuple(res.spin_interval), p)[0])


def _level_tolerance(model) -> tuple[dict, object, list[str]]:
    """How level the base must be (the aligned top's relative equilibrium) and how well aligned
    the magnet (at the scene's base tilt, route Floquet), with the height difference across the
    plate's largest length that the base's tolerance is; the model at the field order of the
    base's tolerance (for the plot); the sentences for the answer's notes.

    The top over a tilted base hovers off the axis, where the field is the Laplace expansion cut at
    the scene's field.order (thesis eqs. 2.2.4-2.2.7): max_base_tilt is computed at higher orders
    too until it changes by less than 1 % (runtime/physics/truncation.py), and reported at the
    order used, with the `truncation` block; max_moment_tilt likewise (moment_tolerance's
    `truncation`) where its route is the relative equilibrium's (about a second an order), not
    where it is shooting (minutes an order): there it stays at the model's order and says so.
    Each order is a progress stage (runtime/ui/progress.py)."""
    from levitron.runtime.physics.rotating_equilibrium import refusal
    from levitron.runtime.physics.tilted_stability import level_tolerance
    from levitron.runtime.physics.truncation import MAX_ORDER, Truncation, by_order
    from levitron.runtime.ui import progress
    p = without_friction(model, model.p)
    n0 = int(model.manifest.field_order)
    orders = range(n0, max(n0, MAX_ORDER) + 1, 2)
    moment = "moment_tilt" in model.param_names
    shooting = refusal(model, p) if moment else None
    names = [f"base tilt (order {n})" for n in orders] + (
        [] if not moment else ["moment tilt"] if shooting else [f"moment tilt (order {n})" for n in orders])
    # shares of the time: the first order ~5 s, each higher one a derivation too (10-40 s); the
    # moment tilt ~1 s an order by the relative equilibrium, minutes by shooting
    weights = [0.3] + [1.0] * (len(orders) - 1) + ([6.0] if shooting else [0.1] * (len(names) - len(orders)))
    load = _loaded_once(model)
    base_at, moment_at = {}, {}

    def base_tilt(m) -> float | None:
        pm = without_friction(m, m.p)
        got = level_tolerance(m, m.with_params({"moment_tilt": 0.0}, pm) if moment else pm)
        base_at[int(m.manifest.field_order)] = (got, m)
        return got["max_base_tilt"]

    def moment_tilt(m) -> float | None:
        got = _moment_tolerance(m, without_friction(m, m.p))
        moment_at[int(m.manifest.field_order)] = got
        return got["max_moment_tilt"]
    with progress.stages("level tolerance", names, weights) as stage:
        trunc = by_order(model, base_tilt, "the largest base tilt (max_base_tilt)", "rad", load=load,
                         stage=lambda n: stage(f"base tilt (order {n})"))
        tol, used = base_at[trunc.order_used]
        tol = dict(tol)
        mtrunc = None
        if moment and not shooting:
            mtrunc = by_order(model, moment_tilt, "the largest moment tilt (max_moment_tilt)", "rad",
                              load=load, stage=lambda n: stage(f"moment tilt (order {n})"))
            tol.update(moment_at[mtrunc.order_used])
        else:
            if moment:
                stage("moment tilt")
            tol.update(_moment_tolerance(model, p))
            if moment:
                mtrunc = Truncation("the largest moment tilt (max_moment_tilt)", "rad", (n0,),
                                    (tol["max_moment_tilt"],), (), n0, unchecked=(
                                        "not checked at higher field orders: its route is shooting, "
                                        f"minutes an order ({shooting})"))
    tol["length"] = model.scene.length_scale
    tol["height_difference"] = (None if tol["max_base_tilt"] is None
                                else math.tan(tol["max_base_tilt"]) * tol["length"])
    tol["truncation"] = trunc.as_json()
    if mtrunc is not None:
        tol["moment_tolerance"] = {**tol["moment_tolerance"], "truncation": mtrunc.as_json()}
    return tol, used, [t.line for t in (trunc, mtrunc) if t is not None and t.line]


def _loaded_once(model):
    """order -> the model at that field order (runtime/physics/truncation.py `loader`), each
    loaded (or refused) once: the base's and the magnet's tolerance share them."""
    from levitron.runtime.physics.truncation import loader
    load, seen = loader(model), {int(model.manifest.field_order): model}

    def once(order: int):
        if order not in seen:
            try:
                seen[order] = load(order)
            except UserError as exc:
                seen[order] = exc
        if isinstance(seen[order], UserError):
            raise seen[order]
        return seen[order]
    return once


def _moment_tolerance(model, p) -> dict:
    """max_moment_tilt (rad) where the model has the moment-tilt terms, else None and why."""
    if "moment_tilt" not in model.param_names:
        return {"max_moment_tilt": None,
                "moment_tolerance": {"note": "the model has no moment-tilt terms: add «set=top.moment_tilt=0» "
                                             "(or the scene's top.moment_tilt)"}}
    from levitron.runtime.physics.floquet_stability import moment_tolerance
    got = moment_tolerance(model, p)
    return {"max_moment_tilt": got.pop("max_moment_tilt"), "moment_tolerance": got}
