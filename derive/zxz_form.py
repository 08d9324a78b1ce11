"""The z-x-z chart's Hamiltonian and Hamilton's equations in a form whose terms do not cancel near
theta = 0 (thesis eqs. 2.3.9-2.3.16).

The Legendre transform (derive/mechanics.py) gives the rotational kinetic energy expanded,

    p_phi^2/(2 A sin^2 th) - p_phi p_psi cos th/(A sin^2 th) + p_psi^2 (A sin^2 th + C cos^2 th)/(2 A C sin^2 th),

whose three terms are each ~ p^2/(A th^2) near the upright top and cancel to ~ p^2/C: at th = 1e-8
the energy of the thesis's top came out 0.60 J off of 0.66 J. The same terms are, exactly,

    T_rot = p_th^2/(2A) + D^2/(2 A sin^2 th) + p_psi^2/(2C),   D = p_phi - p_psi cos th,

(the textbook form of the symmetric top: D / sin th = A times the rate of the line of nodes'
normal component). D itself is a difference of two nearly equal momenta near th = 0 (L_z and L.n);
it is written D = (p_phi - p_psi) + 2 p_psi sin^2(th/2), where p_phi - p_psi is a difference of
the stored momenta (exact in floating point when they are close, Sterbenz) and 1 - cos th is
2 sin^2(th/2), which keeps its relative accuracy. Hamilton's equations that carry the 1/sin th:

    dphi/dt  = D/(A sin^2 th),
    dpsi/dt  = p_psi/C - cos th D/(A sin^2 th),
    dp_th/dt = -dU/dth + D E/(A sin^3 th),     E = p_phi cos th - p_psi = (p_phi - p_psi) - 2 p_phi sin^2(th/2).

Each form is checked equal to the expanded one exactly (sin^2(th/2) = (1 - cos th)/2, then
derive/trig.py) before it is used. What this cannot remove is the chart itself: phi and psi are
undefined at th = 0, the rates D/(A sin^2 th) grow as the axis passes near the vertical (an
adaptive step shrinks there, runtime/integrate/budget.py stops it), and the state stores L_z and
L.n as p_phi and p_psi whose rounding (an ulp of p) is divided by sin th in the transverse rates.
"""
from __future__ import annotations

import sympy as sp

from .symbols import A, C
from .trig import trig_reduce


def _names(q, p) -> tuple:
    """theta and the angular momenta (p_phi, p_theta, p_psi) of the z-x-z state (x, y, z, phi,
    theta, psi; p_x ... p_psi)."""
    assert [str(v) for v in q[3:]] == ["phi", "theta", "psi"], q
    return q[4], p[3], p[4], p[5]


def one_minus_cos(th: sp.Symbol) -> sp.Expr:
    """1 - cos th = 2 sin^2(th/2): no cancellation near th = 0."""
    return 2 * sp.sin(th / 2) ** 2


def transverse(q, p) -> sp.Expr:
    """D = p_phi - p_psi cos th = (p_phi - p_psi) + p_psi (1 - cos th) (module docstring)."""
    th, p_phi, _p_th, p_psi = _names(q, p)
    return (p_phi - p_psi) + p_psi * one_minus_cos(th)


def axial_lag(q, p) -> sp.Expr:
    """E = p_phi cos th - p_psi = (p_phi - p_psi) - p_phi (1 - cos th) (module docstring)."""
    th, p_phi, _p_th, p_psi = _names(q, p)
    return (p_phi - p_psi) - p_phi * one_minus_cos(th)


def rotational_energy(q, p) -> sp.Expr:
    """T_rot = p_th^2/(2A) + D^2/(2 A sin^2 th) + p_psi^2/(2C) (module docstring; thesis eq. 2.3.9)."""
    th, _p_phi, p_th, p_psi = _names(q, p)
    return p_th**2 / (2 * A) + transverse(q, p) ** 2 / (2 * A * sp.sin(th) ** 2) + p_psi**2 / (2 * C)


def full_angle(expr: sp.Expr, th: sp.Symbol) -> sp.Expr:
    """expr with sin(th/2) written through cos th (sin^2(th/2) = (1 - cos th)/2): only even powers
    of sin(th/2) may occur; what derive/trig.py can then reduce."""
    h = sp.Dummy("h")
    e = sp.expand(sp.sympify(expr).xreplace({sp.sin(th / 2): h}))
    poly = sp.Poly(e, h)
    assert all(k % 2 == 0 for (k,) in poly.monoms()), "odd power of sin(th/2)"
    return sp.expand(e.subs(h**2, (1 - sp.cos(th)) / 2))


def same(a: sp.Expr, b: sp.Expr, angles, th) -> bool:
    """a == b exactly, after full_angle (derive/trig.py keeps sin, as the z-x-z chart does)."""
    return trig_reduce(sp.expand(full_angle(a, th) - full_angle(b, th)), angles, "sin") == 0


def cancellation_free(q, p, H: sp.Expr, rhs: sp.Matrix) -> tuple[sp.Expr, sp.Matrix]:
    """(H, rhs) of the z-x-z chart in the forms of the module docstring, each checked equal to the
    expanded H and rhs of the Legendre transform. H is a quadratic form in the momenta plus U, so
    its angular part is what depends on p_phi, p_theta, p_psi; the rest (p^2/2m and U) is kept."""
    th, p_phi, p_th, p_psi = _names(q, p)
    angles = q[3:]
    rest = H.xreplace({p_phi: 0, p_th: 0, p_psi: 0})
    H_new = rest + rotational_energy(q, p)
    assert same(H_new, H, angles, th), "z-x-z: the factored Hamiltonian differs from the expanded one"
    D, E, s = transverse(q, p), axial_lag(q, p), sp.sin(th)
    rows = {3 + 0: D / (A * s**2),                                    # dphi/dt  = dH/dp_phi
            3 + 1: p_th / A,                                          # dth/dt   = dH/dp_th
            3 + 2: p_psi / C - sp.cos(th) * D / (A * s**2),           # dpsi/dt  = dH/dp_psi
            6 + 4: -sp.diff(rest, th) + D * E / (A * s**3)}           # dp_th/dt = -dH/dth
    new = sp.Matrix([rows.get(i, e) for i, e in enumerate(rhs)])
    for i in range(len(rhs)):
        assert i in rows or not new[i].has(p_phi, p_th, p_psi), i
        assert same(new[i], rhs[i], angles, th), f"z-x-z: row {i} of the factored rhs differs"
    return H_new, new
