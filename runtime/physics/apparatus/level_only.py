"""Which answers serve a level base only (plate.tilt = 0): the on-axis analysis of thesis 3.3.

The vertical equilibria, the stable band, the critical spins of thesis 3.3.9-3.3.23 and the designs
and fits built on them (`optimize --maximize` of an interval, `--fit`, `--fit-height`; `figures`
3.5-3.7) rest on the axial symmetry: the top upright on the plate's axis. A tilted base breaks it
(runtime/physics/apparatus/tilted_equilibrium.py: the top hovers off the axis). Those commands refuse a base
that is tilted (base_tilt != 0), naming the level scene's flag; a scene with the tilted model's
terms at tilt 0 (--set plate.tilt=0) is the level apparatus and is answered. `stability`,
`simulate`, `scan`, `launch` and `report` answer for the tilted base. No sympy here.
"""
from __future__ import annotations

from levitron.runtime.errors import UserError


def base_tilt(model) -> float:
    """The model's base tilt (rad; 0 for a model without the tilted terms)."""
    return float(model.pvals()["base_tilt"]) if "base_tilt" in model.param_names else 0.0


def refuse_tilted(model, what: str) -> None:
    """A one-line UserError where the base is tilted: `what` (e.g. "optimize designs") answers for
    the level base only."""
    t = base_tilt(model)
    if t != 0:
        raise UserError(f"{what} for a level base (the top on the plate's axis, thesis 3.3), and scene "
                        f"'{model.scene.name}' has its base tilted by {t:.6g} rad (plate.tilt): pass "
                        "«set» plate.tilt=0 for the level base; stability, simulate, scan, launch and "
                        "report answer for the tilted one")
