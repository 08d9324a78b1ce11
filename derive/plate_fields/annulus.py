"""Thin annulus (thesis eq. 2.2.11), Phi_k cancellation-free (derive/onaxis.py)."""
from __future__ import annotations

import sympy as sp

from .. import onaxis
from ..symbols import Z
from .plate import Plate, axisymmetric, plate_symbol


def build(table: dict, prefix: str = "") -> Plate:
    """Phi0 = 2 pi rho z (1/sqrt(z^2+w^2) - 1/sqrt(z^2+a^2)) (thesis eq. 2.2.11)."""
    a, w, rho = (plate_symbol(prefix + k) for k in ("a", "w", "rho"))
    return axisymmetric("annulus", onaxis.annulus_phis(Z, a, w, 2 * sp.pi * rho), (a, w, rho))
