"""The truncation error of what a top off the axis answers: where it hovers and its spin window.

Over a tilted base (plate.tilt) the top hovers off the plate's axis (runtime/physics/apparatus/tilted_equilibrium.py,
runtime/physics/apparatus/tilted_stability.py), and with its magnet tilted off its own axis (top.moment_tilt)
its steady motion is periodic off it (route "Floquet", runtime/physics/apparatus/moment_tilt.py): both
see the field off the axis, the Laplace expansion phi(r, z) = sum_j (-1)^j r^(2j) / (4^j (j!)^2)
Phi_(2j)(z) of thesis eqs. 2.2.4-2.2.7 cut at field.order. `checked(model, res)` runs
runtime/physics/field/truncation.py's `by_order` on the answer's numbers (`numbers`: the spin window's ends,
the equilibrium's offset from the axis, its height and its axis' angle from the plate's; judged by
the largest relative difference) and returns the answer at the order used: the model's own where
order N + 2 agrees with it to 1 %, else the raised one with a note (a warning where it still moves
at the highest order tried); its `equilibrium` carries the `truncation` block, its notes the line.
thesis_stable over a base tilted by 0.001 rad: the offset is 2.207 mm at order 2 and 2.266 mm at
order 4 (2.6 %; order 6 agrees with 4 to 1e-5): raised to order 4 (the window moves by 0.03 %).

Cost: the answer once more at each order tried (N + 2, then N + 4 ... while it moves): 0.1 s an
order over a tilted base, about 1 s by the relative equilibrium (a tilted magnet over a level
base); each higher order's model derived once into the cache (thesis_stable's tilted model: 8 s at
order 4, 11 s at 6, 20 s at 8 the first time), then loaded from it (about a second). Where the
window is shot (a tilted magnet over a tilted base, or a plate without axial symmetry: 10 s to
minutes an order) the orders are judged by the aligned top's answer (moment tilt 0, the same base:
0.1 s an order, the base's tilt is what moves the top off the axis) and the window is shot once
more, at the order used, only where that is raised. On the axis (a level base, the magnet
aligned) nothing is tried: the expansion is the on-axis potential itself there. No sympy here.
"""
from __future__ import annotations

import dataclasses
import math
import time

from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.physics.field.truncation import MAX_ORDER, Truncation, by_order, loader

WHAT = ("the answer off the axis (the spin window's ends, the top's offset from the axis, its height, "
        "its axis' angle from the plate's)")
ALIGNED = ("the aligned top's answer (moment tilt 0: the spin window's ends, the offset from the axis, the "
           "height, the axis' angle from the plate's; the tilted magnet's window is shot, seconds to minutes "
           "an order)")
UNITS = ("rad/s", "rad/s", "m", "m", "rad")
ON_AXIS = ("the top hovers on the axis (a level base, the magnet aligned): the expansion about the "
           "axis is exact there")


def numbers(res) -> tuple:
    """(lo, hi, offset, height, axis angle) of a StabilityResult; None for what it lacks."""
    lo, hi = (None, None) if res.spin_interval is None else (float(v) for v in res.spin_interval)
    eq = res.equilibrium
    if eq is None:
        return lo, hi, None, None, None
    ax = eq["axis"]
    return lo, hi, float(eq["offset"]), float(eq["position"][2]), math.atan2(math.hypot(ax[0], ax[1]), ax[2])


def _shot(model, p) -> bool:
    """Whether the window of this model's top is found by shooting (its magnet tilted where the
    relative equilibrium does not apply: runtime/physics/apparatus/rotating_equilibrium.py `refusal`)."""
    from levitron.runtime.physics.apparatus.rotating_equilibrium import refusal
    return model.pvals(p).get("moment_tilt", 0.0) != 0 and refusal(model, p) is not None


def _aligned(model):
    """The StabilityResult of the model's top with its magnet aligned (moment tilt 0), same base."""
    from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
    p = without_friction(model, model.p)
    return tilted_analysis(model, model.with_params({"moment_tilt": 0.0}, p) if "moment_tilt" in
                           model.param_names else p)


def checked(model, res, *, load=None, quiet: bool = False):
    """The StabilityResult `res` of `model`'s scene top (runtime/physics/stability/analysis.py stability_of,
    no height given) with its truncation error (module docstring): `res` itself for a model of a
    level base (no base_tilt: on the axis); else the answer at the order used, res's notes with the
    truncation's line after them, `equilibrium["truncation"]` the block (truncation.py as_json)
    and timings["truncation"] the check's seconds. load(order) -> the model at that order (default
    truncation.py `loader`); each order is a progress stage (runtime/ui/progress.py)."""
    from levitron.runtime.physics.stability.analysis import stability_of
    from levitron.runtime.ui import progress
    if "base_tilt" not in model.param_names:
        return res
    t0 = time.perf_counter()
    p = without_friction(model, model.p)
    P = model.pvals(p)
    n0 = int(model.manifest.field_order)
    if P.get("base_tilt", 0.0) == 0 and P.get("moment_tilt", 0.0) == 0:
        return _with(res, res, Truncation(WHAT, UNITS, (n0,), (numbers(res),), (), n0, unchecked=ON_AXIS), t0)
    shot = _shot(model, p)
    load = loader(model) if load is None else load
    models, at = {n0: model}, {}

    def loaded(n: int):
        if n not in models:
            models[n] = load(n)
        return models[n]

    def answer(m) -> tuple:
        n = int(m.manifest.field_order)
        try:
            at[n] = _aligned(m) if shot else (res if n == n0 else stability_of(m))
        except UserError:
            return (None,) * len(UNITS)
        return numbers(at[n])
    orders = list(range(n0, max(n0, MAX_ORDER) + 1, 2))
    with progress.stages("truncation check", [f"field order {n}" for n in orders],
                         [0.2] + [1.0] * (len(orders) - 1), quiet=quiet) as stage:
        trunc = by_order(model, answer, ALIGNED if shot else WHAT, UNITS, load=loaded,
                         stage=lambda n: stage(f"field order {n}"))
    used = at.get(trunc.order_used, res)
    if shot:
        used = stability_of(models[trunc.order_used]) if trunc.raised else res
    return _with(res, used, trunc, t0)


def _with(res, used, trunc: Truncation, t0: float):
    """`used` with res's notes and the truncation's line, its block in `equilibrium`, its time."""
    eq = None if used.equilibrium is None else {**used.equilibrium, "truncation": trunc.as_json()}
    return dataclasses.replace(used, notes=list(res.notes) + ([trunc.line] if trunc.line else []),
                               equilibrium=eq, timings={**used.timings,
                                                        "truncation": time.perf_counter() - t0})
