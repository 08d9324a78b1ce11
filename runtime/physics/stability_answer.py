"""The answer to "at which spin rates does the top hover stably?": what `levitron stability` prints
and `Study.stability()` returns (thesis 3.3).

`Stability.of(model, height, level_tolerance)` runs the analysis (runtime/physics/stability.py:
the exact route, thesis 3.3.9-3.3.16, and the eigenvalue route beside it; over a tilted base the
equilibrium off the axis, runtime/physics/tilted_stability.py) and, on request, how level the base
and how well aligned the magnet must be; `as_json()` is docs/contract.md's `stability` object,
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
    largest base tilt and moment tilt that keep a stable interval (asked for, else None)."""

    result: StabilityResult
    scene: str
    scene_mass: float
    height_given: bool
    eigen_source: str
    stiffness: float | None
    level_tolerance: dict | None = None
    wall_s: float = 0.0
    units: Units = field(default=_SI, compare=False)
    _model: object = field(default=None, compare=False)      # for plot()

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
        tol = _level_tolerance(model) if level_tolerance else None
        wall = time.perf_counter() - t0
        # the vertical stiffness U'' = mu Phi_3(z_s) (thesis 3.3.3), N/m: what «constrain»
        # stiffness>=K of `optimize` speaks of; it does not depend on the mass
        k = (model.param("mu") * float(model.onaxis(res.z_s)[3])
             if res.z_s and res.equilibrium is None else None)
        return cls(res, model.scene.name, model.param("m"), height is not None, eigen, k, tol, wall,
                   Units.of_scene(model.scene), model)

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
        return out

    # ---- actions
    def plot(self, path) -> str | None:
        """Draw the spin interval against the base's tilt up to the tolerance (runtime/physics/tilt_plot.py;
        .png, .pdf, .svg); None where there is no tolerance to draw (no stable interval at all)."""
        if self.level_tolerance is None:
            raise UserError("the plot draws the spin interval against the base's tilt: ask for the "
                            "«level_tolerance»")
        if self.level_tolerance["max_base_tilt"] is None:
            return None
        from levitron.runtime.physics.tilt_plot import draw
        model = self._model
        return str(draw(model, without_friction(model, model.p), self.level_tolerance, path))


def _level_tolerance(model) -> dict:
    """How level the base must be (the aligned top's relative equilibrium) and how well aligned
    the magnet (at the scene's base tilt, route Floquet), with the height difference across the
    plate's largest length that the base's tolerance is."""
    from levitron.runtime.physics.tilted_stability import level_tolerance
    p = without_friction(model, model.p)
    aligned = model.with_params({"moment_tilt": 0.0}, p) if "moment_tilt" in model.param_names else p
    tol = level_tolerance(model, aligned)
    tol.update(_moment_tolerance(model, p))
    tol["length"] = model.scene.length_scale
    tol["height_difference"] = (None if tol["max_base_tilt"] is None
                                else math.tan(tol["max_base_tilt"]) * tol["length"])
    return tol


def _moment_tolerance(model, p) -> dict:
    """max_moment_tilt (rad) where the model has the moment-tilt terms, else None and why."""
    if "moment_tilt" not in model.param_names:
        return {"max_moment_tilt": None,
                "moment_tolerance": {"note": "the model has no moment-tilt terms: add «set=top.moment_tilt=0» "
                                             "(or the scene's top.moment_tilt)"}}
    from levitron.runtime.physics.floquet_stability import moment_tolerance
    got = moment_tolerance(model, p)
    return {"max_moment_tilt": got.pop("max_moment_tilt"), "moment_tolerance": got}
