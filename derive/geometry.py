"""Base plates -> the on-axis magnetic scalar potential Phi0(z) (thesis eqs. 2.2.8-2.2.11).

Every axisymmetric plate is described by Phi0(z), the potential on the z axis, as a sympy expression
in the height `Z` and the plate's parameter symbols (named `plate_<key>`, the names that
derive/scene.py resolves to SI values). The off-axis field follows from Phi0 alone by the Laplace
expansion of derive/field.py (thesis eq. 2.2.6).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import sympy as sp

from .symbols import Z


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
    """

    kind: str
    phi0: sp.Expr
    symbols: tuple[sp.Symbol, ...]
    derivs: Callable[[int], sp.Expr] | None = None
    field3d: Callable[[sp.Expr, sp.Expr, sp.Expr], sp.Matrix] | None = None
    potential3d: Callable[[sp.Expr, sp.Expr, sp.Expr], sp.Expr] | None = None

    @property
    def axisymmetric(self) -> bool:
        return self.field3d is None

    def phi_derivs(self, kmax: int) -> list[sp.Expr]:
        """[Phi_0, ..., Phi_kmax], Phi_k = d^k Phi0 / dz^k (thesis eq. 2.2.6 and after)."""
        out = [self.phi0]
        for k in range(1, kmax + 1):
            out.append(self.derivs(k) if self.derivs else sp.diff(out[-1], Z))
        return out


def annulus_phi0(a: sp.Expr, w: sp.Expr, rho: sp.Expr) -> sp.Expr:
    """Thin annulus of outer radius a, hole w, dipole density rho (thesis eq. 2.2.11):

        Phi0(z) = 2 pi rho z (1/sqrt(z^2 + w^2) - 1/sqrt(z^2 + a^2)).
    """
    return 2 * sp.pi * rho * Z * (1 / sp.sqrt(Z**2 + w**2) - 1 / sp.sqrt(Z**2 + a**2))


def disk_phi0(a: sp.Expr, rho: sp.Expr) -> sp.Expr:
    """Thin disk (thesis eq. 2.2.11 with w = 0, for z > 0): Phi0 = 2 pi rho (1 - z/sqrt(z^2+a^2))."""
    return 2 * sp.pi * rho * (1 - Z / sp.sqrt(Z**2 + a**2))


def build_plate(plate: dict) -> Plate:
    """The Plate for a validated scene's [plate] table (see derive/scene.py).

    Every kind comes from derive/plates_extra.py (imported here because it builds on this module);
    the annulus and disk there have Phi0 of thesis eq. 2.2.11 (`annulus_phi0`, `disk_phi0` above)
    with their derivatives in cancellation-free forms (derive/onaxis.py).
    """
    from .plates_extra import BUILDERS as ALL_BUILDERS
    return ALL_BUILDERS[plate["kind"]](plate)
