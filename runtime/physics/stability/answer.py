"""The answer to "at which spin rates does the top hover stably?": what `levitron stability` prints
and `Study.stability()` returns (thesis 3.3).

`Stability.of(model, height, level_tolerance)` runs the analysis (runtime/physics/stability/analysis.py:
the exact route, thesis 3.3.9-3.3.16, and the eigenvalue route beside it; over a tilted base the
equilibrium off the axis, runtime/physics/apparatus/tilted_stability.py) and, on request, how level the base
(checked against higher orders of the field's expansion, runtime/physics/field/truncation.py) and how
well aligned the magnet must be; `as_json()` is docs/contract.md's `stability` object,
`plot(path)` draws the spin interval against the base's tilt. SI throughout; `units` says how the
repr and the message show the numbers.
"""
from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.physics.stability.analysis import stability_of
from levitron.runtime.physics.routes.result import StabilityResult
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import NOTHING_SAID, said
from levitron.runtime.words import render

_SI = Units(si=True)


@dataclass(frozen=True, repr=False)
class Stability:
    """Linear stability at the hover height (one type: the routes' record, StabilityResult of
    runtime/physics/routes/result.py, is copied into it field by field): z_s (m), spin_interval
    (rad/s, None if no spin stabilises: `reason` says why), the routes' intervals (discriminant,
    eigenvalues: None where not run), approximations (thesis 3.3.22/3.3.23), routes_agree (None
    without a full model), timings, mass (kg: the top analysed; with a height, the one that hovers
    there), notes, equilibrium (over a tilted base: position, axis, offset, ...), floquet (the
    magnet tilted); stiffness: mu Phi_3(z_s) (N/m, thesis 3.3.3; None over a tilted base);
    level_tolerance: the largest base tilt and moment tilt that keep a stable interval (asked for,
    else None); resonances: the low-order resonances among the linear modes inside the spin
    interval (runtime/physics/stability/resonances.py, docs/resonances.md; strongest first), None where not
    computed (no interval, or the steady motion is off the axis). Its words: `lines(units)`
    (runtime/physics/stability/view.py), which the command line prints and message, repr, the
    notebook and the report reuse."""

    z_s: float | None
    spin_interval: tuple[float, float] | None
    discriminant: list
    eigenvalues: list | None
    approximations: dict
    reason: str | None
    routes_agree: bool | None
    timings: dict
    mass: float | None
    notes: list
    equilibrium: dict | None
    floquet: dict | None
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
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, compare=False)   # reason and notes as written (markers)

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
        return cls(**_recorded(res), scene=model.scene.name, scene_mass=model.param("m"),
                   height_given=height is not None, eigen_source=eigen, stiffness=k, level_tolerance=tol,
                   wall_s=wall, units=Units.of_scene(model.scene), _model=drawn, resonances=reso)

    @classmethod
    def from_json(cls, r: dict, units: Units = _SI) -> Stability:
        """The answer again from its as_json() (the command line's plain view reads it so)."""
        iv, ivs = r.get("spin_interval"), r.get("all_intervals") or {}
        return cls(r.get("z_s"), None if iv is None else tuple(iv), ivs.get("discriminant") or [],
                   ivs.get("eigenvalues"), r.get("approximations") or {}, r.get("reason"),
                   r.get("routes_agree"), r.get("timings_s") or {}, r.get("mass"), list(r.get("notes") or []),
                   r.get("equilibrium"), r.get("floquet"), r.get("scene", ""), r.get("scene_mass"),
                   bool(r.get("height_given")), r.get("eigen_source", ""), r.get("stiffness"),
                   r.get("level_tolerance"), r.get("wall_s", 0.0), units, None, r.get("resonances"))

    def record(self) -> StabilityResult:
        """The routes' record of this answer (what runtime/physics/stability/off_axis_truncation.py checks)."""
        return StabilityResult(self.z_s, self.spin_interval, self.discriminant, self.eigenvalues,
                               self.approximations, self.reason, self.routes_agree, self.timings, self.mass,
                               list(self.notes), self.equilibrium, self.floquet)

    def with_record(self, res: StabilityResult) -> Stability:
        """This answer with the routes' record `res` (checked at another field order)."""
        return replace(self, **_recorded(res))

    @property
    def success(self) -> bool:
        """A spin interval of linear stability exists."""
        return self.spin_interval is not None

    # ---- its words, one function for every face (runtime/physics/stability/view.py)
    def lines(self, units: Units | None = None, more=()) -> list[str]:
        """The plain view in `units` (default the scene's): what `levitron stability` prints."""
        from levitron.runtime.physics.stability import view as stability_view
        return stability_view.lines(self, units or self.units, more)

    def summary(self, units: Units | None = None) -> str:
        """The answer in one sentence (the message's, the report's): the interval and where, or why none."""
        from levitron.runtime.physics.stability import view as stability_view
        return stability_view.summary(self, units or self.units)

    @property
    def message(self) -> str:
        return render(self.summary(), "api", self.units)

    def __repr__(self) -> str:
        from levitron.runtime.physics.stability import view
        return render(text_repr("Stability", [view.head(self, self.units), view.where(self, self.units),
                                              f"success={self.success}"]), "api", self.units)

    def _repr_html_(self) -> str:
        figure = None
        if self.level_tolerance is not None and self._model is not None:
            figure = self.plot()
        return render(html_table("Stability", self.lines(), figure), "api", self.units)

    def as_json(self) -> dict:
        """docs/contract.md's `stability` object (SI)."""
        out = {"scene": self.scene, "mass": self.mass, "scene_mass": self.scene_mass,
               "height_given": self.height_given, **self.record().as_dict(), "eigen_source": self.eigen_source}
        if self.level_tolerance is not None:
            out["level_tolerance"] = self.level_tolerance
        out["wall_s"] = self.wall_s
        out["stiffness"] = self.stiffness
        out["resonances"] = None if self.resonances is None else [r.as_json() for r in self.resonances]
        return out

    # ---- actions
    def plot(self, path=None, ax=None):
        """Draw the spin interval against the base's tilt up to the tolerance (runtime/physics/apparatus/tilt_plot.py)
        into `ax` (an Axes) or a figure of its own, written to `path` (.png, .pdf, .svg) only when
        given one. Returns the matplotlib Figure (the Axes when given `ax`); None where there is no
        tolerance to draw (no stable interval at all)."""
        if self.level_tolerance is None:
            raise UserError("the plot draws the spin interval against the base's tilt: ask for the "
                            "«level_tolerance»")
        if self.level_tolerance["max_base_tilt"] is None:
            return None
        from levitron.runtime.physics.apparatus.tilt_plot import draw
        model = self._model
        return draw(model, without_friction(model, model.p), self.level_tolerance, path, ax=ax)


def _recorded(res: StabilityResult) -> dict:
    """The routes' record as the answer's fields, its sentences kept as written (`said`)."""
    iv = res.spin_interval
    return {"z_s": res.z_s, "spin_interval": None if iv is None else tuple(iv), "discriminant": res.discriminant,
            "eigenvalues": res.eigenvalues, "approximations": res.approximations, "reason": res.reason,
            "routes_agree": res.routes_agree, "timings": res.timings, "mass": res.mass, "notes": res.notes,
            "equilibrium": res.equilibrium, "floquet": res.floquet,
            "said": said(reason=res.reason, notes=list(res.notes))}


def resonances_of(model, res: StabilityResult) -> tuple | None:
    """The resonances inside the spin interval (runtime/physics/stability/resonances.py), strongest first;
    None without an interval or where the steady motion is off the axis (a tilted base, the magnet
    off the axis or off the centre: runtime/physics/stability/modes.py OFF_AXIS)."""
    from levitron.runtime.physics.stability.modes import OFF_AXIS
    if res.spin_interval is None or not res.z_s or res.floquet is not None:
        return None
    p = without_friction(model, model.with_params({"m": res.mass}) if res.mass else model.p)
    P = model.pvals(p)
    if any(P.get(k, 0.0) != 0 for k in OFF_AXIS):
        return None
    from levitron.runtime.physics.stability.resonances import find
    return tuple(find(model, res.z_s, tuple(res.spin_interval), p)[0])


def _level_tolerance(model) -> tuple[dict, object, list[str]]:
    """How level the base must be (the aligned top's relative equilibrium) and how well aligned
    the magnet (at the scene's base tilt, route Floquet), with the height difference across the
    plate's largest length that the base's tolerance is; the model at the field order of the
    base's tolerance (for the plot); the sentences for the answer's notes.

    The top over a tilted base hovers off the axis, where the field is the Laplace expansion cut at
    the scene's field.order (thesis eqs. 2.2.4-2.2.7): max_base_tilt is computed at higher orders
    too until it changes by less than 1 % (runtime/physics/field/truncation.py), and reported at the
    order used, with the `truncation` block; max_moment_tilt likewise (moment_tolerance's
    `truncation`) where its route is the relative equilibrium's (about a second an order), not
    where it is shooting (minutes an order): there it stays at the model's order and says so.
    Each order is a progress stage (runtime/ui/progress.py)."""
    from levitron.runtime.physics.apparatus.rotating_equilibrium import refusal
    from levitron.runtime.physics.apparatus.tilted_stability import level_tolerance
    from levitron.runtime.physics.field.truncation import MAX_ORDER, Truncation, by_order
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
    """order -> the model at that field order (runtime/physics/field/truncation.py `loader`), each
    loaded (or refused) once: the base's and the magnet's tolerance share them."""
    from levitron.runtime.physics.field.truncation import loader
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
    from levitron.runtime.physics.apparatus.moment_tilt import moment_tolerance
    got = moment_tolerance(model, p)
    return {"max_moment_tilt": got.pop("max_moment_tilt"), "moment_tolerance": got}
