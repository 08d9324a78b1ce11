"""Which symmetry about the z axis a plate leaves, and what of the model survives it (pure Python).

Every plate kind is centred on the axis and magnetised along z, and a rectangle's sides lie along
x and y, so every plate is symmetric under the mirrors x -> -x and y -> -y. On the axis these
mirrors make B point along z and grad B_z point along z, so the top upright on the axis stays there
(the invariant set of thesis 3.2.1) and the reduced model (thesis eq. 3.2.12) holds for every plate,
with the plate's exact on-axis potential Phi0. What a plate without axial symmetry loses:

- "axial" (no rectangle): energy, L_z and L.n are conserved (derive/invariants.py); the linear
  stability at the axis follows from Phi_k on the axis (thesis 3.3, the discriminant route).
- "four-fold" (the rectangles map onto one another under a quarter turn: a square, a square with a
  hole, any axisymmetric parts besides): energy and L.n are conserved, L_z is not (the cos 4 phi
  part of the field turns the orbit); near the axis the harmonic quadratic terms a (x^2 - y^2) and
  b x y are odd under a quarter turn and so vanish: the field to second order about the axis is
  that of an axisymmetric plate with the same Phi0, and the linear stability still follows from the
  on-axis potential.
- "two-fold" (side_x != side_y): energy and L.n are conserved, L_z is not, and the x^2 - y^2 term
  makes the transverse stiffness differ along x and y: the spin interval from the on-axis potential
  (thesis 3.3) does not hold and is refused; the full model (simulate) uses the exact field.

`symmetry(table, params)` decides it from the plate's resolved parameters (Scene.params, or a
Model's values under --set), since the sides are runtime parameters; what a quarter turn makes of
a part is its kind's `quarter_turn` (None: an axisymmetric kind; scene/plates/base.py).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from . import KINDS
from .compound import SIGN


@dataclass(frozen=True)
class Symmetry:
    name: str                    # "axial", "four-fold" or "two-fold"
    conserved: tuple[str, ...]   # what the full model conserves (without air friction)
    onaxis_stability: bool       # the linear stability at the axis follows from Phi_k (thesis 3.3)
    summary: str                 # one line: the symmetry, what is conserved, what survives

    def as_dict(self) -> dict:
        return {"name": self.name, "conserved": list(self.conserved),
                "onaxis_stability": self.onaxis_stability, "summary": self.summary}


_SUMMARIES = {
    "axial": "axial symmetry: energy, L_z and L.n are conserved; the reduced model (thesis 3.2.12) "
             "and the spin interval from the on-axis potential (thesis 3.3) hold",
    "four-fold": "four-fold symmetry (the rectangle is square): energy and L.n are conserved, L_z is "
                 "not; the reduced model (thesis 3.2.12) and the spin interval from the on-axis "
                 "potential (thesis 3.3) still hold (the field to second order about the axis is "
                 "axisymmetric)",
    "two-fold": "two-fold symmetry (side_x != side_y): energy and L.n are conserved, L_z is not; the "
                "reduced model (thesis 3.2.12) holds, the spin interval from the on-axis potential "
                "(thesis 3.3) does not (the x^2 - y^2 part of the field)",
}
_CONSERVED = {"axial": ("energy", "L_z", "L.n"), "four-fold": ("energy", "L.n"), "two-fold": ("energy", "L.n")}


def _turned(table: Mapping, params: Mapping[str, float], prefix: str, sign: float) -> list[tuple]:
    """(part, part turned a quarter turn) of every part of the plate whose kind is not axisymmetric
    (its kind's `quarter_turn`, scene/plates/base.py), compound parts' with their signs."""
    kind = KINDS.get(table.get("kind")) if isinstance(table.get("kind"), str) else None
    if kind is None:
        return []
    if kind.has_parts:
        out = []
        for i, part in enumerate(table.get("parts") or []):
            part_prefix = f"{prefix}p{i}_"
            s = sign * (float(params[part_prefix + SIGN]) if SIGN in part else 1.0)
            out += _turned(part, params, part_prefix, s)
        return out
    if kind.quarter_turn is None:
        return []
    own = {k[len(prefix):]: float(v) for k, v in params.items()
           if k.startswith(prefix) and k[len(prefix):] != SIGN}
    return [kind.quarter_turn(own, sign)]


def symmetry(table: Mapping, params: Mapping[str, float], prefix: str = "plate_") -> Symmetry:
    """The symmetry the plate `table` (Scene.data["plate"]) leaves with these parameters (module
    docstring): four-fold when the parts without axial symmetry (the rectangles), as a set, map onto
    themselves under a quarter turn."""
    turned = _turned(table, params, prefix, 1.0)
    if not turned:
        name = "axial"
    else:
        name = "four-fold" if sorted(t for _, t in turned) == sorted(p for p, _ in turned) else "two-fold"
    return Symmetry(name, _CONSERVED[name], name != "two-fold", _SUMMARIES[name])
