"""Thin disk (thesis eq. 2.2.11 with w = 0), Phi_k cancellation-free (derive/onaxis.py)."""
from __future__ import annotations

import sympy as sp

from .. import onaxis
from ..symbols import Z
from .plate import Plate, axisymmetric, plate_symbol


def build(table: dict, prefix: str = "") -> Plate:
    """Phi0 = 2 pi rho (1 - z/sqrt(z^2+a^2)) for z > 0."""
    a, rho = plate_symbol(prefix + "a"), plate_symbol(prefix + "rho")
    return axisymmetric("disk", onaxis.disk_phis(Z, a, 2 * sp.pi * rho), (a, rho))
