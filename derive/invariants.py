"""The momenta that Noether's theorem conserves, in canonical variables (thesis 2.3, 3.2).

The field is axially symmetric, so the z-component of the total angular momentum is conserved,

    L_z = x p_y - y p_x + (R_bs I omega)_z,

and the angular momentum about the symmetry axis, L.n = (I omega)_3 = C omega_3, is conserved by
any field (the torque mu n x B is perpendicular to n). omega is the body angular velocity in
canonical variables (derive/friction.py `body_rates`: omega(q, qdot(q, p)), thesis eqs. 3.2.9 and
2.3.8); R_bs the body-to-space rotation (derive/kinematics.py). Both come out short: in Tait-Bryan
angles L.n = -p_zeta, in z-x-z angles L.n = p_psi and L_z = x p_y - y p_x + p_phi. With air
friction L.n decays as exp(-k_spin t) and L_z is no longer conserved.
"""
from __future__ import annotations

import sympy as sp

from .friction import body_rates
from .mechanics import HamiltonianSystem
from .symbols import A, C, X, Y
from .trig import trig_reduce


def angular_momenta(system: HamiltonianSystem) -> tuple[sp.Expr, sp.Expr]:
    """(L_z, L.n) of the module docstring as functions of the canonical state."""
    rot = system.rotation
    simp = lambda e: sp.simplify(trig_reduce(sp.expand(e), rot.angles, rot.keep))  # noqa: E731
    L_body = sp.diag(A, A, C) * body_rates(system)
    L_space_z = (rot.R_bs * L_body)[2]
    px, py = system.p[0], system.p[1]
    return simp(X * py - Y * px + L_space_z), simp(L_body[2])
