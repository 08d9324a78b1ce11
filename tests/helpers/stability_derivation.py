"""Linear stability of the levitron's relative equilibrium, derived symbolically (thesis 3.3).

The thesis follows Dullin & Easton, Physica D 126 (1999) 1-17. Everything below is derived, never
typed in; the thesis's printed forms are kept as `THESIS_*` constants only so that the tests and
docs/errata.md can compare them with the derivation.

Chain of results (thesis equation numbers):

* the relative equilibrium (3.3.4, 3.3.5): x = y = 0, phi = vartheta = 0, z = z_s, all momenta zero
  except p_zeta = C sigma;
* the 12-D Jacobian there (from the full Tait-Bryan Hamiltonian, thesis 3.2.2-3.2.11), which splits
  into the vertical/spin block (z, zeta, p_z, p_zeta) and the 8-D transverse block (the list after
  3.3.5);
* the complex second-order form w'' = A w + B w' with u = dx + i dy, v = dvartheta + i dphi (3.3.6);
* P(lambda) = det(A + lambda B - lambda^2 1) (3.3.8, 3.3.9);
* lambda = i sigma rho t, rho = C/A, with g1, g2, g3 (3.3.10) gives N(t) (3.3.11);
* the discriminant G(g1, g2, g3) of N (3.3.12); along the ray g = l (1, -g21, -g31) (3.3.13, 3.3.14)
  L(l) = G(l, -l g21, -l g31); L at g31 = 0 (3.3.16) and its small-g21 roots (3.3.17, 3.3.18);
* sigma^2 = mu Phi_1 / (l rho^2 A) (this is g1 = l, thesis 3.3.19-3.3.21) and the approximations
  sigma_1^2, sigma_2^2 at z_c (3.3.22, 3.3.23: the thesis prints squares as sigma_1, sigma_2).

Conventions (DESIGN.md): U = m g z - mu n.B, B = -grad(phi), Phi_k = d^k Phi0/dz^k; the field to
second order in r is thesis eq. 2.2.7. P1, P2, P3 below stand for Phi_1(z_s), Phi_2(z_s), Phi_3(z_s).

The runtime needs only numbers: `ray_polynomial_terms()` gives the discriminant G as integer
monomial terms, which runtime/physics/routes/ray_algebra.py hard-codes (tests/derive/test_stability_derivation.py
regenerates
them from here and asserts equality).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from levitron.derive.symbols import Phi, A, C, g, m, mu

# ------------------------------------------------------------------------------------------ symbols

sigma = sp.Symbol("sigma", real=True)           # spin rate: zeta = sigma t, p_zeta = C sigma (3.3.5)
lam = sp.Symbol("lambda")                       # eigenvalue (3.3.7)
t = sp.Symbol("t")                              # lambda = i sigma rho t (after 3.3.9)
l = sp.Symbol("l", real=True)                   # ray parameter (3.3.13)
g1, g2, g3 = sp.symbols("g1 g2 g3", real=True)  # thesis 3.3.10
g21, g31 = sp.symbols("g21 g31", real=True)     # thesis 3.3.14
alpha = sp.Symbol("alpha", positive=True)       # effective length sqrt(A/m) (before 3.3.14)
P1, P2, P3 = sp.symbols("Phi1 Phi2 Phi3", real=True)  # Phi_k(z_s)
z_s = sp.Symbol("z_s", positive=True)
rho = C / A                                     # thesis: "rho is the quotient C/A" (after 3.3.9)

# states of the full Tait-Bryan model, in the order of docs/INTERFACES.md
x, y, z = sp.symbols("x y z", real=True)
phi, vth, zeta = sp.symbols("phi vartheta zeta", real=True)
p_x, p_y, p_z, p_phi, p_vth, p_zeta = sp.symbols("p_x p_y p_z p_phi p_vartheta p_zeta", real=True)
Q_TB = (x, y, z, phi, vth, zeta)
P_TB = (p_x, p_y, p_z, p_phi, p_vth, p_zeta)
STATES_TB = Q_TB + P_TB
# the transverse states, in the order of the thesis's list after 3.3.5
TRANSVERSE = (x, y, vth, phi, p_x, p_y, p_vth, p_phi)
VERTICAL = (z, zeta, p_z, p_zeta)


def equilibrium_point() -> dict:
    """The relative equilibrium (thesis 3.3.4, 3.3.5) as a substitution on the full state."""
    return {x: 0, y: 0, z: z_s, phi: 0, vth: 0, zeta: 0,
            p_x: 0, p_y: 0, p_z: 0, p_phi: 0, p_vth: 0, p_zeta: C * sigma}


def _phi_to_symbols(expr: sp.Expr) -> sp.Expr:
    """Replace Phi(k, z_s) by the plain symbols Phi1, Phi2, Phi3 (and Phi(k) others by new symbols)."""
    reps = {}
    for f in expr.atoms(Phi):
        k = int(f.args[0])
        reps[f] = {1: P1, 2: P2, 3: P3}.get(k, sp.Symbol(f"Phi{k}", real=True))
    return expr.xreplace(reps)


# ------------------------------------------- route 1: the full Hamiltonian of derive/mechanics.py

@dataclass(frozen=True)
class HamiltonianSystem:
    """q, p, H(q, p) and the right-hand side [dH/dp, -dH/dq] (thesis 2.3.10)."""

    q: tuple
    p: tuple
    H: sp.Expr

    @property
    def rhs(self) -> sp.Matrix:
        return sp.Matrix([sp.diff(self.H, pi) for pi in self.p]
                         + [-sp.diff(self.H, qi) for qi in self.q])


@lru_cache(maxsize=None)
def full_hamiltonian() -> HamiltonianSystem:
    """The full Tait-Bryan Hamiltonian of derive/mechanics.py (thesis 2.3.9 in the angles of 3.2.2,
    field to order r^2, eq. 2.2.7), with its states renamed to this module's symbols."""
    from levitron.derive.mechanics import hamiltonian_system
    sys_ = hamiltonian_system("tait-bryan", 2)
    ren = {old: new for old, new in zip(tuple(sys_.q) + tuple(sys_.p), STATES_TB)}
    return HamiltonianSystem(Q_TB, P_TB, sp.sympify(sys_.H).xreplace(ren))


# ------------------------------------------------------------------------ linearisation (3.3.5)

def jacobian_at_equilibrium(system: HamiltonianSystem) -> sp.Matrix:
    """The 12x12 Jacobian of Hamilton's equations at the relative equilibrium (3.3.4, 3.3.5).

    Rows/columns in the order x, y, z, phi, vartheta, zeta, p_x, ..., p_zeta (INTERFACES.md).
    Phi_k(z_s) are replaced by the symbols Phi1, Phi2, Phi3.
    """
    rhs = system.rhs
    pt = equilibrium_point()
    return sp.Matrix([[sp.cancel(_phi_to_symbols(sp.diff(f, s).xreplace(pt))) for s in STATES_TB]
                      for f in rhs])


def _select(J: sp.Matrix, rows, cols) -> sp.Matrix:
    idx = {s: i for i, s in enumerate(STATES_TB)}
    return sp.Matrix([[J[idx[r], idx[c]] for c in cols] for r in rows])


def split_blocks(J: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix, sp.Matrix]:
    """(transverse 8x8, vertical 4x4, transverse<-vertical, vertical<-transverse) blocks of J."""
    return (_select(J, TRANSVERSE, TRANSVERSE), _select(J, VERTICAL, VERTICAL),
            _select(J, TRANSVERSE, VERTICAL), _select(J, VERTICAL, TRANSVERSE))


@lru_cache(maxsize=None)
def linear_system_8d() -> sp.Matrix:
    """The 8-D linear system after thesis 3.3.5: d/dt (dx, dy, dvth, dphi, dp_x, dp_y, dp_vth, dp_phi),
    the transverse block of the full model's Jacobian at the relative equilibrium."""
    J8, _, _, _ = split_blocks(jacobian_at_equilibrium(full_hamiltonian()))
    return J8


def small_angle_system_8d() -> sp.Matrix:
    """The same 8-D system from the quadratic small-angle Hamiltonian (a second, shorter route).

    To second order about the upright top: n = (vth, phi, 1 - (vth^2 + phi^2)/2),
    U2 = -mu Phi3 r^2/4 - mu Phi2 (x vth + y phi)/2 - mu Phi1 (vth^2 + phi^2)/2 (from 2.2.7),
    and the rotational kinetic energy with p_zeta fixed gives
    H2 = (p_x^2 + p_y^2)/(2m) + p_vth^2/(2A) + (p_phi - p_zeta vth)^2/(2A) + U2.
    """
    pz = C * sigma
    H2 = ((p_x ** 2 + p_y ** 2) / (2 * m) + p_vth ** 2 / (2 * A) + (p_phi - pz * vth) ** 2 / (2 * A)
          - mu * P3 * (x ** 2 + y ** 2) / 4 - mu * P2 * (x * vth + y * phi) / 2
          - mu * P1 * (vth ** 2 + phi ** 2) / 2)
    q = (x, y, vth, phi)
    p = (p_x, p_y, p_vth, p_phi)
    rhs = [sp.diff(H2, pi) for pi in p] + [-sp.diff(H2, qi) for qi in q]
    return sp.Matrix(rhs).jacobian(sp.Matrix(TRANSVERSE)).applyfunc(sp.expand)


def thesis_system_8d() -> sp.Matrix:
    """The thesis's list after 3.3.5 as printed, rows in the printed order.

    The 4th line is printed as 'd vth/dt = -p_zeta/A dvth + dp_phi/A'; it can only be d phi/dt
    (a duplicate left-hand side). Rows here: dx, dy, dvth, dvth(printed; = dphi), dp_x, dp_y,
    dp_vth, dp_phi, in terms of the columns TRANSVERSE.
    """
    pz = C * sigma
    rows = {
        x: {p_x: 1 / m},
        y: {p_y: 1 / m},
        vth: {p_vth: 1 / A},
        phi: {vth: -pz / A, p_phi: 1 / A},       # printed with d(vartheta)/dt on the left
        p_x: {x: mu * P3 / 2, vth: mu * P2 / 2},
        p_y: {y: mu * P3 / 2, phi: mu * P2 / 2},
        p_vth: {x: mu * P2 / 2, vth: mu * P1 - pz ** 2 / A, p_phi: pz / A},
        p_phi: {y: mu * P2 / 2, phi: mu * P1},
    }
    return sp.Matrix([[rows[r].get(c, 0) for c in TRANSVERSE] for r in TRANSVERSE])


# --------------------------------------------------------------------- complex form (3.3.6)

def second_order_form(J8: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """Eliminate the momenta: q'' = K q + D q' for q = (dx, dy, dvth, dphi) (real 4x4 K, D)."""
    Jqq, Jqp = J8[:4, :4], J8[:4, 4:]
    Jpq, Jpp = J8[4:, :4], J8[4:, 4:]
    Jqp_inv = Jqp.inv()
    K = Jqp * Jpq - Jqp * Jpp * Jqp_inv * Jqq
    D = Jqq + Jqp * Jpp * Jqp_inv
    return K.applyfunc(sp.simplify), D.applyfunc(sp.simplify)


def realify(M: sp.Matrix) -> sp.Matrix:
    """The real 4x4 matrix acting on (Re u, Im u, Re v, Im v) ordered as (x, y, vth, phi)."""
    out = sp.zeros(4, 4)
    for i in range(2):
        for j in range(2):
            re, im = sp.re(M[i, j]), sp.im(M[i, j])
            out[2 * i, 2 * j], out[2 * i, 2 * j + 1] = re, -im
            out[2 * i + 1, 2 * j], out[2 * i + 1, 2 * j + 1] = im, re
    return out


def complex_form() -> tuple[sp.Matrix, sp.Matrix]:
    """A and B of thesis 3.3.6 (u = dx + i dy, v = dvartheta + i dphi), derived:

        A = [[mu Phi3/(2m), mu Phi2/(2m)], [mu Phi2/(2A), mu Phi1/A]],   B = diag(0, -i sigma C/A).
    """
    return (sp.Matrix([[mu * P3 / (2 * m), mu * P2 / (2 * m)], [mu * P2 / (2 * A), mu * P1 / A]]),
            sp.Matrix([[0, 0], [0, -sp.I * sigma * C / A]]))


# ---------------------------------------------------------------- P(lambda), N(t) (3.3.8-3.3.11)

def P_of_lambda() -> sp.Expr:
    """P(lambda) = det(A + lambda B - lambda^2 1) (thesis 3.3.8), expanded. Correct form of 3.3.9:

        lambda^4 + i sigma rho lambda^3 - mu (Phi1/A + Phi3/(2m)) lambda^2
        - i sigma rho mu Phi3/(2m) lambda + mu^2 (2 Phi1 Phi3 - Phi2^2)/(4 m A).
    """
    Am, Bm = complex_form()
    return sp.expand((Am + lam * Bm - lam ** 2 * sp.eye(2)).det())


# the thesis's 3.3.9 as printed (note mu, not mu^2, in the constant term; odd terms of opposite sign)
THESIS_P = (lam ** 4 - sp.I * sigma * rho * lam ** 3 - mu * (P1 / A + P3 / (2 * m)) * lam ** 2
            + sp.I * sigma * rho * mu * P3 / (2 * m) * lam + mu * (2 * P1 * P3 - P2 ** 2) / (4 * m * A))

G_DEFS = {  # thesis 3.3.10
    g1: mu * P1 / (sigma ** 2 * rho ** 2 * A),
    g2: mu * P2 / (2 * sigma ** 2 * rho ** 2 * sp.sqrt(m * A)),
    g3: mu * P3 / (2 * sigma ** 2 * rho ** 2 * m),
}

# thesis 3.3.11 as printed
N_THESIS = t ** 4 - t ** 3 + (g1 + g3) * t ** 2 - g3 * t + g1 * g3 - g2 ** 2


def to_g(expr: sp.Expr) -> sp.Expr:
    """Rewrite an expression in Phi1, Phi2, Phi3 as one in g1, g2, g3 (inverse of 3.3.10)."""
    s2r2 = sigma ** 2 * rho ** 2
    reps = {P1: g1 * s2r2 * A / mu, P3: 2 * g3 * s2r2 * m / mu}
    e = sp.expand(expr.subs(reps))
    # Phi2 enters P only as Phi2^2 (mu^2 Phi2^2 = 4 g2^2 s2r2^2 m A)
    e = e.subs(P2 ** 2, 4 * g2 ** 2 * s2r2 ** 2 * m * A / mu ** 2)
    return sp.expand(sp.simplify(e))


def N_from_P(sign: int = +1) -> sp.Expr:
    """P(lambda = sign * i sigma rho t) / (sigma rho)^4 in g1, g2, g3.

    With the correct P (sign = +1) this is N(-t) of the thesis's 3.3.11; with sign = -1 it is N(t).
    Either way the real roots correspond: lambda on the imaginary axis <=> t real.
    """
    e = P_of_lambda().subs(lam, sign * sp.I * sigma * rho * t) / (sigma * rho) ** 4
    return to_g(e)


# ------------------------------------------------------------------- discriminant G (3.3.12)

@lru_cache(maxsize=None)
def discriminant_G() -> sp.Expr:
    """G(g1, g2, g3) = discriminant of N(t) in t (thesis 3.3.12), expanded."""
    return sp.expand(sp.discriminant(sp.Poly(N_THESIS, t)).as_expr())


THESIS_G = sp.sympify(
    "16*g1*g3**5 - 4*g3**5 - 16*g2**2*g3**4 - 64*g1**2*g3**4 + 48*g1*g3**4 - 8*g3**4"
    " + 192*g1*g2**2*g3**3 - 60*g2**2*g3**3 + 96*g1**3*g3**3 - 88*g1**2*g3**3 + 32*g1*g3**3"
    " - 4*g3**3 - 128*g2**4*g3**2 - 352*g1**2*g2**2*g3**2 + 124*g1*g2**2*g3**2 - 12*g2**2*g3**2"
    " - 64*g1**4*g3**2 + 48*g1**3*g3**2 - 8*g1**2*g3**2 + 512*g1*g2**4*g3 - 48*g2**4*g3"
    " + 192*g1**3*g2**2*g3 - 196*g1**2*g2**2*g3 + 36*g1*g2**2*g3 + 16*g1**5*g3 - 4*g1**4*g3"
    " - 256*g2**6 - 128*g1**2*g2**4 + 144*g1*g2**4 - 27*g2**4 - 16*g1**4*g2**2 + 4*g1**3*g2**2",
    locals={"g1": g1, "g2": g2, "g3": g3})


# ------------------------------------------------------------ the ray L(l) (3.3.13-3.3.18)

def g_ratios() -> dict:
    """g21 = -g2/g1 and g31 = -g3/g1 in terms of Phi_k and alpha = sqrt(A/m) (thesis 3.3.14)."""
    mp = sp.Symbol("m_pos", positive=True)  # a mass is positive: sqrt(m^2) = m
    e21 = sp.simplify((-G_DEFS[g2] / G_DEFS[g1]).subs({m: mp, A: alpha ** 2 * mp}))
    e31 = sp.simplify((-G_DEFS[g3] / G_DEFS[g1]).subs({m: mp, A: alpha ** 2 * mp}))
    return {g21: e21.subs(mp, m), g31: e31.subs(mp, m)}


@lru_cache(maxsize=None)
def L_of_l() -> sp.Expr:
    """L(l) = G(l, -l g21, -l g31) (thesis 3.3.13): the ray g = l (1, -g21, -g31), i.e. l = g1."""
    return sp.expand(discriminant_G().subs({g1: l, g2: -l * g21, g3: -l * g31}, simultaneous=True))


def L_reduced() -> sp.Expr:
    """-L(l)/l^3: the cubic in l whose positive roots are the critical points of the ray."""
    return sp.expand(sp.cancel(-L_of_l() / l ** 3))


def L_at_g31_zero() -> sp.Expr:
    """The quadratic left of L(l) at g31 = 0 after removing the factor -g21^2 l^4 (thesis 3.3.16):

        16 (4 g21^2 + 1)^2 l^2 - (144 g21^2 + 4) l + 27 g21^2.
    """
    return sp.expand(sp.cancel(L_of_l().subs(g31, 0) / (-(g21 ** 2) * l ** 4)))


THESIS_L16 = -16 * (4 * g21 ** 2 + 1) ** 2 * l ** 2 + (144 * g21 + 4) * l - 27 * g21 ** 2


def critical_l_at_g31_zero() -> list[sp.Expr]:
    """The two roots of L(l, g31 = 0), smaller first (exact; real for g21^2 < 1/12, thesis 3.3.15)."""
    Q = L_at_g31_zero()
    a2, a1, a0 = sp.Poly(Q, l).all_coeffs()
    root = sp.sqrt(a1 ** 2 - 4 * a2 * a0)
    return [sp.simplify((-a1 - root) / (2 * a2)), sp.simplify((-a1 + root) / (2 * a2))]


def sigma_squared_of_l() -> sp.Expr:
    """sigma^2 for the ray point l: from g1 = l, sigma^2 = mu Phi1 / (l rho^2 A) (thesis 3.3.10, 3.3.21)."""
    S = sp.Symbol("S", positive=True)
    return sp.solve(sp.Eq(G_DEFS[g1].subs(sigma, sp.sqrt(S)), l), S)[0]


def sigma_squared_thesis_forms() -> list[sp.Expr]:
    """The four expressions of thesis 3.3.21 for sigma_i^2 with l_i = l (under m g = -mu Phi2)."""
    return [m * g * alpha / (2 * rho * l * g21 * C),
            g * A / (2 * rho * l * g21 * alpha * C),
            g / (2 * rho ** 2 * l * g21 * alpha),
            -g * P1 / (rho ** 2 * l * alpha ** 2 * P2)]


def sigma_approximations() -> dict:
    """sigma_1^2 and sigma_2^2 at z_c (Phi3 = 0) from l1 ~ 1/4, l2 ~ 27 g21^2 / 4 (thesis 3.3.22/23).

    These are squares of rates; the thesis prints them as sigma_1 and sigma_2.
    """
    s2 = -g * P1 / (rho ** 2 * l * alpha ** 2 * P2)
    return {"sigma1_sq": sp.simplify(s2.subs(l, sp.Rational(1, 4))),
            "sigma2_sq": sp.simplify(s2.subs(l, sp.Rational(27, 4) * g_ratios()[g21] ** 2))}


THESIS_SIGMA1 = -4 * g * P1 / (P2 * alpha ** 2 * rho ** 2)                      # 3.3.22 as printed
THESIS_SIGMA2 = sp.Rational(16, 27) * (-P1 / P2) ** 3 * g / (alpha ** 4 * rho ** 2)  # 3.3.23 as printed


# ------------------------------------------------------ numbers for the runtime (no sympy there)

def ray_polynomial_terms() -> list[list[int]]:
    """G(g1, g2, g3) as sorted integer terms [coefficient, e1, e2, e3] (thesis 3.3.12).

    Along the spin ray g_i = s c_i (s = 1/sigma^2, c_i = g_i sigma^2), G(s c) = sum over terms of
    coef c1^e1 c2^e2 c3^e3 s^(e1+e2+e3); runtime/physics/routes/ray_algebra.py hard-codes this list as G_TERMS.
    """
    poly = sp.Poly(discriminant_G(), g1, g2, g3)
    return sorted(([int(c), *map(int, e)] for e, c in poly.terms()), key=lambda r: r[1:])
