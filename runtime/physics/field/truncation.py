"""How much an answer moves with the order of the field's expansion: its truncation error.

The model's field off the plate's axis is the Laplace expansion of the on-axis potential,
phi(r, z) = sum_j (-1)^j r^(2j) / (4^j (j!)^2) Phi_(2j)(z) (thesis eqs. 2.2.4-2.2.6, B = -grad phi,
eq. 2.2.7), cut at the scene's `field.order` (derive/field.py). An answer that depends on the field
off the axis (how far the base may tilt: the top then hovers off the axis) moves with that cut:
thesis_stable's largest base tilt is 0.00165 rad at order 2 and 0.00143 rad at order 6, where
higher orders agree with it to 1e-3. The answers of a top off the axis (its equilibrium over a tilted
base and the spin window there) are checked alike (runtime/physics/stability/off_axis_truncation.py); a launch's
field at its farthest reach off the axis against the exact field's (runtime/scan/launch_inputs.py).

The method, `by_order(model, answer, ...)`: the answer at the model's own order N, then at N + 2
(the same scene and overrides with «set=field.order=N+2», derived once into the cache and then
loaded from it), and again 2 higher while the relative difference between the last two exceeds
RTOL, up to MAX_ORDER. The answer reported (`order_used`) is the model's own when the next order
agrees with it to RTOL (it stands as it was and nothing is said), else the one at the highest
order reached, with a note; a warning when the difference still exceeds RTOL there (at MAX_ORDER,
or where a higher order could not be derived). Nothing is tried where the model's field has no
expansion to cut (a plain rectangle's exact field) or its order is already MAX_ORDER or more; the
result says why. No sympy here: a model at another order comes from the derivation subprocess
(runtime/model/load.py).
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from levitron.runtime.errors import UserError
from levitron.runtime.words import si

RTOL = 0.01          # an answer that changes by more than this between two orders is not converged
# the highest order the check derives by itself: thesis_stable's tilted model derives (and
# compiles) in 8 s at order 4, 11 s at 6, 20 s at 8, 26 s at 10 and 43 s at 12 on 2 cores
MAX_ORDER = 10
SCENE_MAX_ORDER = 12  # the highest field.order a scene takes (scene/load.py)


@dataclass(frozen=True)
class Truncation:
    """The answer at each field order tried. relative_differences[i] is |v_i - v_(i+1)| / |v_(i+1)|
    between orders[i] and orders[i+1] (None where one of them has no answer); order_used the order
    whose answer is reported; warning: the answer still moves by more than RTOL at the highest
    order reached; note: the line the answer shows (the order raised, or why it was not checked
    though it should have been); unchecked: why no higher order was tried (None if one was)."""

    what: str
    unit: str | tuple[str, ...]
    orders: tuple[int, ...]
    values: tuple    # a number (or a tuple of numbers) or None at each order
    relative_differences: tuple[float | None, ...]
    order_used: int
    warning: str | None = None
    note: str | None = None
    unchecked: str | None = None
    rtol: float = RTOL
    max_order: int = MAX_ORDER

    @property
    def value(self) -> float | None:
        """The answer at order_used."""
        return self.values[self.orders.index(self.order_used)]

    @property
    def raised(self) -> bool:
        return self.order_used != self.orders[0]

    @property
    def line(self) -> str | None:
        """What the answer says of its truncation (the warning, else the note), or None."""
        return self.warning or self.note

    def as_json(self) -> dict:
        return {"orders": list(self.orders),
                "values": [list(v) if isinstance(v, tuple) else v for v in self.values],
                "relative_difference": list(self.relative_differences), "order_used": self.order_used,
                "rtol": self.rtol, "max_order": self.max_order, "warning": self.warning, "note": self.note,
                "unchecked": self.unchecked}


def relative_difference(lower, higher) -> float | None:
    """|lower - higher| / |higher| (0 where both are None or equal; None where only one is None
    or higher is 0 and lower not: no relative size). An answer of several numbers (a tuple): the
    largest of its numbers' (None where one of them is None)."""
    if lower is None and higher is None:
        return 0.0
    if lower is None or higher is None:
        return None
    if isinstance(lower, tuple):
        each = [relative_difference(a, b) for a, b in zip(lower, higher, strict=True)]
        return None if None in each else max(each, default=0.0)
    if lower == higher:
        return 0.0
    return abs(lower - higher) / abs(higher) if higher != 0 else None


def expanded(plate: dict) -> bool:
    """Whether a plate's field in the model is (in part) the expansion about the axis: as its kind
    declares (scene/plates/base.py `exact_field`: a rectangle without a hole is exact), and a
    compound's where one of its parts is (Scene.data["plate"], derive/plate_fields/plate.py)."""
    from levitron.scene.plates import KINDS
    kind = KINDS.get(plate.get("kind"))
    if kind is not None and kind.has_parts:
        return any(expanded(part) for part in plate.get("parts") or ())
    return kind is None or kind.exact_field is None or not kind.exact_field(plate)


def loader(model) -> Callable[[int], object]:
    """order -> the model of the same scene and overrides with field.order = order (derived into
    the cache the first time)."""
    from levitron.runtime.model.load import load_model
    from levitron.runtime.model.scenes import load_scene
    ref = model.ref

    def load(order: int):
        return load_model(load_scene(*ref.with_overrides([f"field.order={order}"])))
    return load


def _shown(v, unit) -> str:
    """A number (or a tuple of them, with a tuple of units) in a sentence."""
    if isinstance(v, tuple):
        return "(" + ", ".join(_shown(x, u) for x, u in zip(v, unit, strict=True)) + ")"
    return "none" if v is None else si(v, unit)


def _percent(d: float | None) -> str:
    return "an answer at one order and none at the other" if d is None else f"{d * 100:.2g} %"


def by_order(model, answer: Callable[[object], object], what: str, unit, *,
             load: Callable[[int], object] | None = None, stage: Callable[[int], None] | None = None,
             rtol: float = RTOL, max_order: int = MAX_ORDER) -> Truncation:
    """`answer(model)` at the model's field order and higher ones (module docstring). what: the
    answer's name in a sentence; unit: its SI unit (an answer of several numbers: a tuple of them
    and a tuple of their units, judged by the largest relative difference); load(order) -> the model at that order
    (default `loader(model)`); stage(order), if given, is called as the answer at an order begins."""
    n0 = int(model.manifest.field_order)
    if stage is not None:
        stage(n0)
    orders, values, diffs = [n0], [answer(model)], []
    if not expanded(model.scene.data["plate"]):
        return Truncation(what, unit, (n0,), tuple(values), (), n0, rtol=rtol, max_order=max_order, unchecked=(
            "the plate's field is exact in the model (no expansion about the axis): nothing to truncate"))
    if n0 >= max_order:
        return Truncation(what, unit, (n0,), tuple(values), (), n0, rtol=rtol, max_order=max_order, unchecked=(
            f"the model's field order {n0} is at or above the check's highest, {max_order}: no "
            "higher order tried"))
    load = loader(model) if load is None else load
    failed = None
    while orders[-1] + 2 <= max_order:
        n = orders[-1] + 2
        if stage is not None:
            stage(n)
        try:
            higher = load(n)
        except UserError as exc:
            failed = f"order {n} could not be derived: {exc}"
            break
        orders.append(n)
        values.append(answer(higher))
        diffs.append(relative_difference(values[-2], values[-1]))
        if diffs[-1] is not None and diffs[-1] <= rtol:
            break
    done = dict(what=what, unit=unit, orders=tuple(orders), values=tuple(values),
                relative_differences=tuple(diffs), rtol=rtol, max_order=max_order)
    if not diffs:
        return Truncation(**done, order_used=n0, unchecked=failed, note=(
            f"{what} ({_shown(values[0], unit)}) is at field order {n0} and not checked against a "
            f"higher order of the expansion about the axis (thesis eq. 2.2.6): {failed}"))
    if diffs[0] is not None and diffs[0] <= rtol:
        return Truncation(**done, order_used=n0)
    top, last = orders[-1], diffs[-1]
    moved = (f"{what} is {_shown(values[0], unit)} at field order {n0} and {_shown(values[-1], unit)} "
             f"at order {top}: the expansion about the axis (thesis eq. 2.2.6) cut at order {n0} "
             f"moves it by {_percent(relative_difference(values[0], values[-1]))}")
    if last is not None and last <= rtol:
        return Truncation(**done, order_used=top, note=(
            f"{moved}; the answer is order {top}'s (it changes by {_percent(last)} from order "
            f"{orders[-2]} to {top})"))
    why = failed or f"order {top} is the highest the check derives"
    nxt = (f"derive a higher one with «set=field.order={top + 2}»" if top + 2 <= SCENE_MAX_ORDER
           else f"no scene takes an order above {SCENE_MAX_ORDER}: compare with the exact field")
    return Truncation(**done, order_used=top, warning=(
        f"{moved}, and still by {_percent(last)} from order {orders[-2]} to {top} ({why}): the "
        f"answer (order {top}'s) may be off by as much; {nxt}"), unchecked=failed)

