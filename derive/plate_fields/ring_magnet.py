"""Axially magnetised ring magnet (or solid cylinder), top face in z = 0 (Derby & Olbert 2010)."""
from __future__ import annotations

from levitron.scene.plates.ring_magnet import hollow

from .. import onaxis
from ..symbols import Z
from .plate import MU0_SYM, Plate, axisymmetric, plate_symbol


def build(table: dict, prefix: str = "") -> Plate:
    """r_in <= r <= r_out, -t <= z <= 0, magnetisation M (A/m). On the axis
    B_z = (mu0 M/2) sum_R +-[(z+t)/sqrt((z+t)^2+R^2) - z/sqrt(z^2+R^2)] (outer +, inner -).
    Structural decision `hollow` (r_in > 0, scene/plates/ring_magnet.py): the inner term."""
    r_out, t, mag = (plate_symbol(prefix + k) for k in ("r_out", "thickness", "magnetization"))
    strength = MU0_SYM * mag / 2
    outer = onaxis.cylinder_phis(Z, r_out, t, strength)
    if hollow(table):
        r_in = plate_symbol(prefix + "r_in")
        inner = onaxis.cylinder_phis(Z, r_in, t, strength)
        return axisymmetric("ring_magnet", lambda k: outer(k) - inner(k), (r_out, r_in, t, mag))
    return axisymmetric("ring_magnet", outer, (r_out, t, mag))
