"""Low-order resonances among the linear modes inside the spin interval (docs/resonances.md).

Inside the window every mode is on the imaginary axis (thesis 3.3.11: N(t) has four real roots),
yet the top is not equally robust everywhere: where the modes' frequencies are commensurate the
nonlinear terms exchange energy between them resonantly, and where a mode of negative energy
(runtime/physics/stability/modes.py: its Krein sign) takes part, the amplitudes may all grow together.

A resonance of order r is a relation sum_k p_k omega_k = 0 among the frequencies omega_k signed by
their sense (+ with the spin; the bounce's positive), integers p_k with sum |p_k| = r, no common
divisor, at least two modes. The normal form's resonant term, prod of the amplitudes and
cos(sum n_k theta_k) with theta_k the modes' angles, exists only if the base's symmetry allows it: a
turn by alpha about the axis advances a transverse mode's phase by alpha (azimuthal number 1 in
the sense-signed convention, the bounce 0), so sum of p_k over the transverse modes (the
"m-balance") must be 0 for an axisymmetric base, 0 mod 4 for a four-fold one, 0 mod 2 for a
two-fold one (scene/plates/symmetry.py). With kappa_k the energy signs, the normal-form angles turn
at kappa_k |omega_k|, and n_k = p_k s_k kappa_k (s_k the sense, +1 for the bounce); the resonant
dynamics keep the combinations |n_l| J_k - sgn(n_k n_l) |n_k| J_l of the actions J constant: where
the n_k are of mixed signs the actions are bounded, where they all share one sign they may all grow
without bound, in finite time at order 3 (an explosive instability: Cairns, J. Plasma Phys. 22, 149
(1979); Craik, Wave interactions and fluid flows (1985), ch. 6; Kueny & Morrison, Phys. Plasmas 2,
1926 (1995)). For the triad omega_1 = omega_2 + omega_3 of positive frequencies: explosive exactly
when wave 1's energy sign is opposite to waves 2's and 3's. At order 4 the amplitude-dependent
detuning of the quartic normal form competes with the resonant term: "explosive" there says the
signs allow it.

Each relation is tabulated over a log grid of the window and every sign change is brought to a root
by Brent's method (runtime/physics/routes/brent.py) on the modes' frequencies (the order of the signed
frequencies does not change inside the window, so each is continuous there). No sympy here.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.physics.routes.brent import brentq
from levitron.runtime.physics.routes.eigen_route import balancing
from levitron.runtime.physics.stability.modes import LinearSystem, Mode
from levitron.runtime.words import si

ORDERS = (3, 4)
GRID = 40               # spins on the window's log grid
EDGE = 1e-6             # the grid stays this far (relative) inside the window's ends
FOLD = {"axial": 0, "four-fold": 4, "two-fold": 2}


def _vectors(n: int, budget: int):
    if n == 0:
        yield ()
        return
    for c in range(-budget, budget + 1):
        for rest in _vectors(n - 1, budget - abs(c)):
            yield (c, *rest)


@functools.lru_cache(maxsize=8)
def relations(n_modes: int = 5, orders=ORDERS) -> tuple[tuple[int, ...], ...]:
    """Every integer vector p over n_modes of order sum |p_k| in `orders`, at least two modes, no
    common divisor, its first nonzero entry positive."""
    out = []
    for p in _vectors(n_modes, max(orders)):
        nz = [c for c in p if c]
        if len(nz) < 2 or sum(map(abs, p)) not in orders or nz[0] < 0 or math.gcd(*nz) != 1:
            continue
        out.append(p)
    return tuple(out)


def m_balance(p, azimuthal) -> int:
    """The net azimuthal number sum p_k m_k (m_k 1 for a transverse mode, 0 for the bounce)."""
    return int(sum(c * m for c, m in zip(p, azimuthal)))


def allowed(balance: int, fold: int) -> bool:
    """The selection rule: the m-balance is 0 (fold 0: an axisymmetric base), or 0 mod fold."""
    return balance == 0 if fold == 0 else balance % fold == 0


def explosive(p, modes) -> bool:
    """All n_k = p_k s_k kappa_k of one sign (module docstring); False where a sign is undefined."""
    n = [c * (m.sense or 1) * m.krein for c, m in zip(p, modes) if c]
    return all(x > 0 for x in n) or all(x < 0 for x in n)


def relation_text(p, names, senses) -> str:
    """"slow precession = translation(+1) + vertical bounce" among the frequencies |omega_k|: the
    coefficients c_k = p_k s_k (the sense absorbed; the bounce's +1), c_k > 0 on one side, < 0 on
    the other, the side with fewer terms on the left."""
    c = [q * (s or 1) for q, s in zip(p, senses)]

    def side(sign):
        return [f"{abs(k)} {n}" if abs(k) > 1 else n for k, n in zip(c, names) if k * sign > 0]
    a, b = side(1), side(-1)
    if len(a) > len(b):
        a, b = b, a
    return f"{' + '.join(a)} = {' + '.join(b)}"


@dataclass(frozen=True)
class Resonance:
    spin: float
    order: int
    relation: str
    coefficients: tuple[tuple[str, int], ...]
    m_balance: int
    explosive: bool
    frequencies: tuple[tuple[str, float], ...]   # signed, rad/s, at the spin
    krein: tuple[tuple[str, int], ...]

    @property
    def kind(self) -> str:
        return f"{self.order}-wave"

    def as_json(self) -> dict:
        return {"spin": self.spin, "order": self.order, "relation": self.relation,
                "coefficients": dict(self.coefficients), "m_balance": self.m_balance,
                "explosive": self.explosive, "frequencies": dict(self.frequencies),
                "krein": dict(self.krein)}


def find(model, z_s: float, window: tuple[float, float], p: np.ndarray | None = None,
         orders=ORDERS) -> tuple[list[Resonance], str]:
    """The resonances of `orders` inside the window (lo, hi) allowed by the plate's symmetry, the
    strongest first (lowest order, explosive first, nearest the window's middle), and the symmetry's
    name."""
    from levitron.scene.plates.symmetry import symmetry
    ls = LinearSystem(model, z_s, p, hessian="jacobian")
    sym = symmetry(model.scene.data["plate"], ls.P).name
    fold = FOLD[sym]
    lo, hi = window
    grid = np.geomspace(lo * (1 + EDGE), hi * (1 - EDGE), GRID)
    d = balancing(ls.jacobian(math.sqrt(lo * hi)))
    cache: dict[float, np.ndarray] = {}

    def omega(s: float) -> np.ndarray:
        if s not in cache:
            cache[s] = ls.signed(s, d)
        return cache[s]
    table = np.array([omega(s) for s in grid])
    if table.shape[1] != 5:
        return [], sym
    azimuthal = [0, 1, 1, 1, 1]
    P = np.array([q for q in relations(5, orders) if allowed(m_balance(q, azimuthal), fold)])
    F = table @ P.T
    found = []
    for i, k in zip(*np.nonzero(np.sign(F[:-1]) * np.sign(F[1:]) < 0)):
        q = P[k]
        at = brentq(lambda s, q=q: float(omega(s) @ q), grid[i], grid[i + 1], xtol=1e-12 * hi)
        modes: tuple[Mode, ...] = ls.modes(at, d=d)
        scale = max(abs(m.frequency) for m, c in zip(modes, q) if c)
        if abs(sum(c * m.signed for c, m in zip(q, modes))) > 1e-6 * scale:
            continue        # a jump (two modes swapped), not a root
        names = [m.name for m in modes]
        found.append(Resonance(
            float(at), int(np.abs(q).sum()), relation_text(q, names, [m.sense for m in modes]),
            tuple((n, int(c)) for n, c in zip(names, q) if c), m_balance(q, azimuthal),
            explosive(q, modes), tuple((n, m.signed) for n, m, c in zip(names, modes, q) if c),
            tuple((n, m.krein) for n, m, c in zip(names, modes, q) if c)))
    mid = 0.5 * (lo + hi)
    found.sort(key=lambda r: (r.order, not r.explosive, abs(r.spin - mid) / (hi - lo)))
    return found, sym


def summary(found: list[Resonance]) -> str:
    """"strongest: 3-wave, explosive, at ‹213.4|rad/s› (slow precession = ...)" or why none."""
    if not found:
        return "no resonance of order 3 or 4 inside the spin interval"
    r = found[0]
    return (f"strongest: {r.kind}, {'explosive' if r.explosive else 'bounded'}, at {si(r.spin, 'rad/s', '.4g')} "
            f"({r.relation})")
