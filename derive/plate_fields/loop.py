"""Circular current loop in z = 0 (Jackson eq. 5.40 on the axis)."""
from __future__ import annotations

from .. import onaxis
from ..symbols import Z
from .plate import MU0_SYM, Plate, axisymmetric, plate_symbol


def build(table: dict, prefix: str = "") -> Plate:
    """Loop of radius a and current I: B_z = mu0 I a^2 / (2 (z^2+a^2)^1.5) on the axis,
    Phi0 = (mu0 I/2)(1 - z/sqrt(z^2+a^2)) (z > 0): the thin disk of dipole density D = I."""
    a, cur = plate_symbol(prefix + "a"), plate_symbol(prefix + "current")
    return axisymmetric("loop", onaxis.disk_phis(Z, a, MU0_SYM * cur / 2), (a, cur))
