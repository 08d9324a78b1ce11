"""The derive side's plate object: the on-axis potential and parameters of a base plate (sympy).

Every plate is described by Phi0(z), the potential on the z axis (thesis eq. 2.2.6 at r = 0), as
a sympy expression in the height `Z` and the plate's parameter symbols (named `plate_<key>`, the
names that the registry's resolvers give Scene.params). The off-axis field follows from Phi0 alone
by the Laplace expansion of derive/field.py (thesis eq. 2.2.6), or, for a plate without axial
symmetry, from its exact 3-D field; a plate with both (a rectangle with a hole, a compound of a
rectangle and a ring) has the exact field of its non-axisymmetric parts plus the expansion of its
axisymmetric ones (`Plate.model_field`).
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp

from levitron.scene.constants import MU0

from ..field import field
from ..symbols import Phi, Z, phi_orders

MU0_SYM = sp.Float(MU0)


def plate_symbol(key: str) -> sp.Symbol:
    """The symbol of a plate parameter; its value comes from Scene.params['plate_<key>']."""
    return sp.Symbol(f"plate_{key}", real=True)


@dataclass(frozen=True)
class Plate:
    """A base plate: its on-axis potential and parameters.

    phi0:     Phi0(z) (thesis eq. 2.2.6 with r = 0), linear in the strength symbol.
    symbols:  the plate's parameter symbols, in the order they enter the parameter vector.
    derivs:   optional callable k -> Phi_k(z) in a better-conditioned form than differentiating
              phi0 k times (a plate may supply cancellation-free forms).
    field3d:  for a plate without axial symmetry (kind "rectangle"): callable (x, y, z) -> B as a
              sympy Matrix (3x1), exact; the full model must use it instead of the expansion.
              phi0 is then its exact on-axis potential (used by `onaxis` and the reduced model).
    potential3d: likewise (x, y, z) -> phi with B = -grad(phi).
    axial:    for a plate with field3d and axisymmetric parts besides (a rectangle's hole, a
              compound's rings): k -> Phi_k of those parts alone, whose field the full model adds
              to field3d by the Laplace expansion to the scene's order (thesis eqs. 2.2.6-2.2.7);
              phi0 and derivs are then the whole plate's (field3d's on-axis part plus these).
    """

    kind: str
    phi0: sp.Expr
    symbols: tuple[sp.Symbol, ...]
    derivs: Callable[[int], sp.Expr] | None = None
    field3d: Callable[[sp.Expr, sp.Expr, sp.Expr], sp.Matrix] | None = None
    potential3d: Callable[[sp.Expr, sp.Expr, sp.Expr], sp.Expr] | None = None
    axial: Callable[[int], sp.Expr] | None = None

    @property
    def axisymmetric(self) -> bool:
        return self.field3d is None

    def model_field(self, order: int, x, y, z) -> sp.Matrix:
        """The 3-D field the full model uses for a plate without axial symmetry: field3d, plus the
        Laplace expansion to `order` (thesis eq. 2.2.7 generalised, derive/field.py) of the axial
        parts' Phi_k, substituted. Without axial parts it is field3d itself."""
        B = sp.Matrix(self.field3d(x, y, z))
        if self.axial is None:
            return B
        expansion = field(order, x, y, z)
        orders = sorted(phi_orders(expansion))
        return B + expansion.xreplace({Phi(k, z): self.axial(k).xreplace({Z: z}) for k in orders})

    def phi(self, k: int) -> sp.Expr:
        """Phi_k: the plate's own (cancellation-free) form when it has one, else d^k Phi0/dz^k."""
        if k == 0:
            return self.phi0
        return self.derivs(k) if self.derivs is not None else sp.diff(self.phi0, Z, k)

    def phi_derivs(self, kmax: int) -> list[sp.Expr]:
        """[Phi_0, ..., Phi_kmax], Phi_k = d^k Phi0 / dz^k (thesis eq. 2.2.6 and after)."""
        out = [self.phi0]
        for k in range(1, kmax + 1):
            out.append(self.derivs(k) if self.derivs else sp.diff(out[-1], Z))
        return out


def axisymmetric(kind: str, phis: Callable[[int], sp.Expr], symbols) -> Plate:
    """A Plate from k -> Phi_k (k = 0 included)."""
    return Plate(kind, phis(0), tuple(symbols), phis)
