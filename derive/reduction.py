"""The invariant set and the reduced 4-D model (thesis eqs. 3.2.1, 3.2.12 and the equations after it).

On I = {x = y = 0, phi = vartheta = 0, p_x = p_y = 0, p_phi = p_vartheta = 0} (thesis eq. 3.2.1, in
Dullin's angles of thesis 3.2.2) the full Tait-Bryan vector field is tangent to I (tests check it),
so the motion stays in I and is governed by the restriction of H:

    H_I(z, zeta, p_z, p_zeta) = p_z^2/(2m) + p_zeta^2/(2C) + mu Phi_1(z) + m g z   (thesis eq. 3.2.12)
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .mechanics import hamiltonian_system


@dataclass(frozen=True)
class ReducedSystem:
    state: tuple          # (z, zeta, p_z, p_zeta)
    H: sp.Expr            # H_I, thesis eq. 3.2.12
    rhs: sp.Matrix        # Hamilton's equations of H_I (the 4-D system after thesis eq. 3.2.12)
    invariant_set: dict   # the substitution that defines I (thesis eq. 3.2.1)

    @property
    def state_names(self) -> list[str]:
        return [str(v) for v in self.state]


def invariant_set(full) -> dict:
    """I of thesis eq. 3.2.1 as a substitution on the full Tait-Bryan state."""
    x, y, _z, phi, vth, _zeta = full.q
    px, py, _pz, pphi, pvth, _pzeta = full.p
    return {x: 0, y: 0, phi: 0, vth: 0, px: 0, py: 0, pphi: 0, pvth: 0}


def reduced_system(order: int = 2) -> ReducedSystem:
    """Restrict the full Tait-Bryan model to I (thesis eqs. 3.2.1, 3.2.12)."""
    full = hamiltonian_system("tait-bryan", order)
    I = invariant_set(full)
    z, zeta = full.q[2], full.q[5]
    pz, pzeta = full.p[2], full.p[5]
    H = sp.expand(full.H.xreplace(I))
    q, p = (z, zeta), (pz, pzeta)
    rhs = sp.Matrix([sp.diff(H, v) for v in p] + [-sp.diff(H, v) for v in q])
    return ReducedSystem((z, zeta, pz, pzeta), H, rhs, I)
