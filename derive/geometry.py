"""Base plates -> the on-axis magnetic scalar potential Phi0(z) (thesis eqs. 2.2.8-2.2.11).

The plates themselves live in the registry: scene/plates/<kind>.py (scene keys, resolver,
structural decisions) and derive/plate_fields/<kind>.py (the sympy builder, imported from here
as `build_plate`). This module keeps the thesis's textbook Phi0 of the annulus and the disk, which
tests compare the registry's cancellation-free forms (derive/onaxis.py) against.
"""
from __future__ import annotations

import sympy as sp

from .plate_fields import Plate, build_plate, plate_symbol
from .symbols import Z

__all__ = ["Plate", "annulus_phi0", "build_plate", "disk_phi0", "plate_symbol"]


def annulus_phi0(a: sp.Expr, w: sp.Expr, rho: sp.Expr) -> sp.Expr:
    """Thin annulus of outer radius a, hole w, dipole density rho (thesis eq. 2.2.11):

        Phi0(z) = 2 pi rho z (1/sqrt(z^2 + w^2) - 1/sqrt(z^2 + a^2)).
    """
    return 2 * sp.pi * rho * Z * (1 / sp.sqrt(Z**2 + w**2) - 1 / sp.sqrt(Z**2 + a**2))


def disk_phi0(a: sp.Expr, rho: sp.Expr) -> sp.Expr:
    """Thin disk (thesis eq. 2.2.11 with w = 0, for z > 0): Phi0 = 2 pi rho (1 - z/sqrt(z^2+a^2))."""
    return 2 * sp.pi * rho * (1 - Z / sp.sqrt(Z**2 + a**2))
