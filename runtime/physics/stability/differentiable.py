"""Stability quantities as differentiable CasADi Functions of the parameter vector (thesis 3.3).

Every symbolic piece is sympy's: the plate's on-axis functions Phi_0..Phi_K (thesis eq.
2.2.6) are the generated CasADi Function `onaxis` (generated/<scene>/onaxis.casadi), and the ray
polynomial G (thesis eq. 3.3.12) is derived in sympy by tests/helpers/stability_derivation.py and
committed as `runtime.physics.routes.ray_algebra.G_TERMS` (tests/derive/test_stability_derivation.py regenerates
it). This module only composes them:

* z_s: root of F(z; p) = m g + mu Phi_2(z) (thesis 3.3.2) with mu Phi_3 > 0 (3.3.3);
* z_c: root of Phi_3(z; p) (the largest hovering mass, 3.3.3);
* sigma_lo, sigma_hi: the critical spins, s = 1/sigma^2 the positive roots of the ray cubic
  Q(s) = G(s c1, s c2, s c3) / s^3 (thesis 3.3.13-3.3.16) at z_s, between which the top is
  linearly stable;
* the stable band (docs/contract.md "The stable band"): its lower edge z_lo = z_c with the
  largest mass m(z_c), and its upper edge z_hi with the mass m(z_hi), where the two critical
  spins of the stable interval merge. There the ray crosses the cuspidal edge of the quartic's
  discriminant surface: N(t) (thesis 3.3.11) has a triple root t0, N = (t - t0)^3 (t - 1 + 3 t0).
  The discriminant of the ray cubic in s therefore has a triple zero in z (separation of the
  two spins ~ (z_hi - z)^(3/2); measured on thesis_stable), useless for Newton, but the system
  N = N' = N'' = 0 in (z, s, t0) is regular (its Jacobian is nonsingular on every scene), so
  z_hi is an implicit function with exact derivatives; `band_function`.

Each is an implicit function, solved by `casadi.rootfinder` (Newton) from a starting point the
exact float routes supply (runtime/physics/equilibrium/finder.py, runtime/physics/routes/ray_algebra.py); CasADi then
gives
exact derivatives with respect to every parameter by the implicit function theorem. Residuals are
divided by the 2-norm of their terms (the sensitivities at the root are unchanged: only
the Newton tolerances see the scaling), and the unknowns are the ratios to their starting
values, so the rootfinder's tolerances are relative whatever the units. No sympy here.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from levitron.runtime.errors import UserError
from levitron.runtime.physics.routes.ray_algebra import _g_poly_by_degree

NEWTON = {"abstol": 1e-15, "abstolStep": 1e-15, "max_iter": 40, "error_on_fail": False}
# inside an NLP: tolerances every well-conditioned root reaches, a failure is an evaluation error
NEWTON_STRICT = {"abstol": 1e-12, "abstolStep": 1e-14, "max_iter": 40, "error_on_fail": True}


@dataclass(frozen=True)
class Symbols:
    """The residuals of one model as CasADi expressions of (z, s, p); built by `symbols`."""

    p: ca.SX
    names: list[str]
    onaxis: ca.Function

    def par(self, name: str):
        return self.p[self.names.index(name)]

    def phis(self, z):
        return self.onaxis(z, self.p)

    def hover(self, z, mass=None):
        """(m g + mu Phi_2(z)) / |(m g, mu Phi_2)| (thesis 3.3.2), normalised."""
        m = self.par("m") if mass is None else mass
        a, b = m * self.par("g"), self.par("mu") * self.phis(z)[2]
        return (a + b) / _norm([a, b])

    def stiffness(self, z):
        """U''(z) = mu Phi_3(z) (thesis 3.3.3), N/m."""
        return self.par("mu") * self.phis(z)[3]

    def phi3_normalised(self, z):
        """Phi_3(z) / |(Phi_2/z, Phi_3)|: zero at z_c (thesis 3.3.3)."""
        ph = self.phis(z)
        return ph[3] / _norm([ph[2] / z, ph[3]])

    def hover_mass(self, z):
        """m(z) = -mu Phi_2(z) / g, the mass that hovers at z (thesis 3.3.2)."""
        return -self.par("mu") * self.phis(z)[2] / self.par("g")

    def ray(self, z, mass=None):
        """(c1, c2^2, c3) = g_i sigma^2 (thesis 3.3.10) for the top of mass `mass` (default m) at
        z, as runtime.physics.routes.ray_algebra.RayCoefficients."""
        ph = self.phis(z)
        m = self.par("m") if mass is None else mass
        A, C, mu = self.par("A"), self.par("C"), self.par("mu")
        return (mu * ph[1] * A / C ** 2, mu ** 2 * ph[2] ** 2 * A ** 3 / (4 * C ** 4 * m),
                mu * ph[3] * A ** 2 / (2 * C ** 2 * m))

    def cubic(self, s, z, mass=None):
        """Coefficient terms [a0, a1 s, a2 s^2, a3 s^3] of the ray cubic Q(s) = G(s c)/s^3 (thesis
        3.3.13) for the top of mass `mass` (default m) at z."""
        a = _g_poly_by_degree(*self.ray(z, mass), ca.SX(1))
        return [a[k] * s ** k for k in range(4)]

    def q(self, s, z, mass=None):
        """Q(s) / |terms|, normalised (zero at a critical spin s = 1/sigma^2)."""
        t = self.cubic(s, z, mass)
        return sum(t) / _norm(t)

    def four_real(self, s, z, mass=None):
        """[G, P, D] of N(t) (thesis 3.3.11) at s, each normalised by the 2-norm of its terms:
        N has four distinct real roots (transverse linear stability) iff G > 0, P < 0
        and D < 0, with P = 8 a c - 3 b^2 and D = 64 e - 16 c^2 + 16 b^2 c - 16 b d - 3 b^4 the
        quartic's classical invariants (a = 1, b = -1, c = s (c1 + c3), d = -s c3,
        e = s^2 (c1 c3 - c2^2))."""
        c1, c2sq, c3 = self.ray(z, mass)
        c, d, e = s * (c1 + c3), -s * c3, s ** 2 * (c1 * c3 - c2sq)
        P = [8 * c, ca.SX(-3)]
        D = [64 * e, -16 * c ** 2, 16 * c, 16 * d, ca.SX(-3)]
        return [self.q(s, z, mass), sum(P) / _norm(P), sum(D) / _norm(D)]

    def slope(self, s, z, mass=None):
        """s dQ/ds / |terms of Q| at s, normalised like `q`."""
        t = self.cubic(s, z, mass)
        return sum(k * t[k] for k in range(1, 4)) / _norm(t)

    def simple_neighbours(self, s1, s2, z, mass=None):
        """-slope(s1) slope(s2): > 0 iff the roots s1 < s2 of Q are neighbours (the third root
        lies outside [s1, s2]; Q' = a3 (s - s_j)(s - s_k) + ... changes sign between them). A
        polynomial in the coefficients, smooth also where a3 changes sign and the third root
        passes through infinity."""
        return -self.slope(s1, z, mass) * self.slope(s2, z, mass)


def _norm(terms):
    """The 2-norm of a list of terms (smooth, unlike the sum of magnitudes)."""
    return ca.sqrt(sum(t ** 2 for t in terms))


def simple_neighbours(a, s1: float, s2: float) -> float:
    """Symbols.simple_neighbours for a float cubic a = [a0, a1, a2, a3] (the float twin)."""
    def slope(s):
        t = [a[k] * s ** k for k in range(4)]
        return sum(k * t[k] for k in range(1, 4)) / sum(v * v for v in t) ** 0.5
    return -slope(s1) * slope(s2)


def symbols(model) -> Symbols:
    """The Symbols of a loaded runtime.model.load.Model (its generated `onaxis` CasADi Function)."""
    names = model.param_names
    return Symbols(ca.SX.sym("p", len(names)), names, model.casadi("onaxis"))


def _root(name: str, unknowns: list[str], outputs: list[str], residual, value_of, sy: Symbols,
          strict: bool = False):
    """casadi.Function name(<unknown>_guess..., p) -> outputs: Newton on residual(values) with
    values = guess * v (v ~ 1), v the rootfinder's unknowns; value_of(values) -> output list.
    strict: a Newton failure is an evaluation error (inside an NLP IPOPT then shortens its step)."""
    n = len(unknowns)
    v = ca.SX.sym("v", n)
    guess = ca.SX.sym("guess", n)
    values = [guess[i] * v[i] for i in range(n)]
    opts = dict(NEWTON_STRICT if strict else NEWTON)
    res = ca.Function(f"{name}_residual", [v, guess, sy.p], [ca.vertcat(*residual(values))])
    try:
        rf = ca.rootfinder(f"{name}_newton", "newton", res, opts)
    except RuntimeError as exc:        # casadi: a residual that does not depend on its unknowns
        if "singular" not in str(exc):
            raise
        raise UserError(f"the {name} function cannot be built: its residual does not depend on "
                        f"{', '.join(unknowns)} (the plate's on-axis functions are constant in z, a "
                        "formula without a field?); check the plate with `«levitron=equilibrium»`") from None
    g_in = [ca.SX.sym(f"{u}_guess") for u in unknowns]
    sol = rf(ca.DM.ones(n), ca.vertcat(*g_in), sy.p)
    vals = [g_in[i] * sol[i] for i in range(n)]
    return ca.Function(name, [*g_in, sy.p], value_of(vals), [f"{u}_guess" for u in unknowns] + ["p"],
                       outputs)


def z_s_function(sy: Symbols) -> ca.Function:
    """z_s(z_guess, p) -> z_s, stiffness: the hover height (thesis 3.3.2) and mu Phi_3 there."""
    return _root("z_s", ["z"], ["z_s", "stiffness"], lambda v: [sy.hover(v[0])],
                 lambda v: [v[0], sy.stiffness(v[0])], sy)


def z_c_function(sy: Symbols) -> ca.Function:
    """z_c(z_guess, p) -> z_c, max_mass: the zero of Phi_3 and m(z_c) (thesis 3.3.3)."""
    return _root("z_c", ["z"], ["z_c", "max_mass"], lambda v: [sy.phi3_normalised(v[0])],
                 lambda v: [v[0], sy.hover_mass(v[0])], sy)


def spin_function(sy: Symbols, strict: bool = False) -> ca.Function:
    """spin(z_guess, sigma_lo_guess, sigma_hi_guess, p) -> z_s, sigma_lo, sigma_hi (rad/s): the
    critical spins at the hover height, s = 1/sigma^2 roots of the ray cubic (thesis 3.3.13-3.3.16)."""
    def residual(v):
        z, lo, hi = v
        return [sy.hover(z), sy.q(1 / lo ** 2, z), sy.q(1 / hi ** 2, z)]
    return _root("spin", ["z", "sigma_lo", "sigma_hi"], ["z_s", "sigma_lo", "sigma_hi"], residual,
                 lambda v: list(v), sy, strict)


def triple_root(sy: Symbols, z, s, t):
    """N(t) = (t - t0)^3 (t - 1 + 3 t0), t0 = t, at s = 1/sigma^2 for the top of mass m(z) hovering at z:
    the quartic of thesis 3.3.11 matched coefficient by coefficient (t^2, t^1, t^0), each residual
    normalised by the 2-norm of its terms."""
    c1, c2sq, c3 = sy.ray(z, sy.hover_mass(z))
    rows = [[3 * t, -6 * t ** 2, -s * c1, -s * c3],
            [3 * t ** 2, -8 * t ** 3, -s * c3],
            [t ** 3, -3 * t ** 4, -s ** 2 * c1 * c3, s ** 2 * c2sq]]
    return [sum(r) / _norm(r) for r in rows]


def band_function(sy: Symbols, strict: bool = False) -> ca.Function:
    """band(z_c_guess, z_hi_guess, s_guess, t_guess, p) -> z_lo, z_hi (m), m_hi, m_lo (kg),
    mass_window (1): the stable band's edges, z_lo = z_c (Phi_3 = 0, thesis 3.3.3) and z_hi where
    N(t) has a triple root at the merging critical spin s = 1/sigma^2 (thesis 3.3.11-3.3.16), the
    masses m(z) = -mu Phi_2(z)/g there (3.3.2) and (m_hi - m_lo) / m_hi."""
    def residual(v):
        return [sy.phi3_normalised(v[0]), *triple_root(sy, v[1], v[2], v[3])]

    def value_of(v):
        m_hi, m_lo = sy.hover_mass(v[0]), sy.hover_mass(v[1])
        return [v[0], v[1], m_hi, m_lo, (m_hi - m_lo) / m_hi]
    return _root("band", ["z_c", "z_hi", "s", "t"], ["z_lo", "z_hi", "m_hi", "m_lo", "mass_window"],
                 residual, value_of, sy, strict)


# the residuals `_root` solves, as functions of the roots (the first outputs): `batch` checks them
RESIDUALS = {"z_s": lambda sy, v: [sy.hover(v[0])],
             "z_c": lambda sy, v: [sy.phi3_normalised(v[0])],
             "spin": lambda sy, v: [sy.hover(v[0]), sy.q(1 / v[1] ** 2, v[0]),
                                    sy.q(1 / v[2] ** 2, v[0])]}

def residual_at(sy: Symbols, name: str, roots, p) -> float:
    """The largest normalised residual of rootfinder `name` (RESIDUALS) at the given roots and
    parameters p: the floor Newton cannot go below there (rounding in the scene's functions)."""
    v = ca.SX.sym("v", len(roots))
    f = ca.Function("residual", [v, sy.p], [ca.mmax(ca.fabs(ca.vertcat(*RESIDUALS[name](sy, v))))])
    return float(f(ca.DM(list(roots)), p))


FUNCTIONS = {"z_s": z_s_function, "z_c": z_c_function, "spin": spin_function,
             "band": band_function}


# ------------------------------------------------ evaluation from the float routes' starting points

@dataclass(frozen=True)
class Starts:
    """Starting points from the exact float routes (runtime/physics/equilibrium/finder.py, ray_algebra.py):
    z_s (m), the spin interval at z_s (rad/s), z_c (m); None where the quantity does not exist."""

    z_s: float | None
    spin: tuple[float, float] | None
    z_c: float | None
    stiffness: float | None = None                 # mu Phi_3(z_s), N/m
    intervals: tuple[tuple[float, float], ...] = ()  # every bounded stable spin interval at z_s
    band: tuple[float, float, float] | None = None   # (z_hi, s, t0) near the band's upper edge


def starts(model, p=None, band: bool = False) -> Starts:
    """The float routes' answers at p (default the scene's) to start the rootfinders from; with
    band=True also the stable band's upper edge (runtime/physics/equilibrium/bands.py, `band_start`)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    p = model.p if p is None else p
    rep = eqm.equilibria_of(model, p, bands=band)
    edge = band_start(model, p, rep.stable_band) if band and rep.stable_band else None
    z_s = rep.stable[0].z if rep.stable else None
    if z_s is None:
        return Starts(None, None, rep.z_c, band=edge)
    bounded = spin_intervals(model, p, z_s)
    return Starts(z_s, bounded[0] if bounded else None, rep.z_c, rep.stable[0].stiffness, bounded,
                  edge)


def spin_intervals(model, p, z_s: float) -> tuple[tuple[float, float], ...]:
    """Every bounded stable spin interval (rad/s) of the top hovering at z_s (the float route,
    runtime/physics/routes/ray_algebra.py), lowest first."""
    import math

    from levitron.runtime.physics.routes.ray_algebra import RayCoefficients, spin_intervals_discriminant
    P = model.pvals(p)
    ph = model.onaxis(z_s, p)
    c = RayCoefficients.from_physics(ph[1], ph[2], ph[3], P["m"], P["A"], P["C"], P["mu"])
    return tuple(iv for iv in spin_intervals_discriminant(c) if 0 < iv[0] and iv[1] < math.inf)


def spin_guesses(model, p, z_s: float) -> list[float] | None:
    """guesses("spin", ...) at a known hover height z_s: [z_s, sigma_lo, sigma_hi] of the first
    bounded stable interval there, or None."""
    bounded = spin_intervals(model, p, z_s)
    return [z_s, *bounded[0]] if bounded else None


def band_start(model, p, band) -> tuple[float, float, float] | None:
    """(z, s, t0) to start `band_function`'s z_hi from: a height just inside the float band's
    upper edge (runtime/physics/equilibrium/bands.py), the middle s of its (nearly merged) stable spin interval and
    the mean of the three clustered roots of N(t) there (thesis 3.3.11)."""
    import numpy as np

    from levitron.runtime.physics.routes.ray_algebra import RayCoefficients, spin_intervals_discriminant
    P = model.pvals(p)
    lo, hi = band.z
    for frac in (1e-6, 1e-4, 1e-2):
        z = hi - frac * (hi - lo)
        ph = model.onaxis(z, p)
        m = -P["mu"] * ph[2] / P["g"]
        c = RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, P["A"], P["C"], P["mu"])
        bounded = [iv for iv in spin_intervals_discriminant(c) if 0 < iv[0] and iv[1] < np.inf]
        if bounded:
            s = 1 / (bounded[0][0] * bounded[0][1])
            c1, c2sq, c3 = c.floats()
            t = np.sort(np.roots([1, -1, s * (c1 + c3), -s * c3, s * s * (c1 * c3 - c2sq)]).real)
            k = min(range(2), key=lambda i: t[i + 2] - t[i])
            return float(hi), float(s), float(t[k:k + 3].mean())
    return None


def guesses(name: str, st: Starts) -> list[float] | None:
    """The starting values of Function `name` (FUNCTIONS) from the float routes, or None."""
    if name == "z_s":
        return None if st.z_s is None else [st.z_s]
    if name == "z_c":
        return None if st.z_c is None else [st.z_c]
    if name == "band":
        return None if st.band is None or st.z_c is None else [st.z_c, *st.band]
    return None if st.spin is None else [st.z_s, *st.spin]


class CasadiStability:
    """The Functions of FUNCTIONS for one model, built once; `values(p)` and `jacobian(p)` start
    them from the float routes at p."""

    def __init__(self, model):
        self.model = model
        self.symbols = symbols(model)
        self.functions = {k: f(self.symbols) for k, f in FUNCTIONS.items()}
        self._batches: dict = {}

    def values(self, p=None, st: Starts | None = None) -> dict[str, float]:
        """{output name: value} of every Function whose quantity exists at p (SI units)."""
        p = self.model.p if p is None else p
        st = starts(self.model, p, band=True) if st is None else st
        out = {}
        for name, F in self.functions.items():
            g = guesses(name, st)
            if g is not None:
                res = F(*g, p)
                res = res if isinstance(res, tuple) else (res,)
                out.update({F.name_out(i): float(v) for i, v in enumerate(res)})
        return out

    def jacobian(self, output: str, p=None, st: Starts | None = None):
        """d output / d p (a row, parameter order model.param_names), exact (implicit function
        theorem through the rootfinder), or None where the quantity does not exist."""
        import numpy as np
        p = self.model.p if p is None else p
        st = starts(self.model, p, band=True) if st is None else st
        for name, F in self.functions.items():
            if output in F.name_out():
                g = guesses(name, st)
                if g is None:
                    return None
                y = F(*[ca.DM(v) for v in g], self.symbols.p)
                y = y if isinstance(y, tuple) else (y,)
                J = ca.Function("J", [self.symbols.p], [ca.jacobian(y[F.index_out(output)],
                                                                    self.symbols.p)])
                return np.asarray(J(p), float).reshape(-1)
        raise UserError(f"unknown quantity {output!r}: use one of {', '.join(self.outputs())}")

    def batch(self, name: str, n: int) -> ca.Function:
        """Function `name` (z_s, z_c or spin) mapped over n parameter vectors in one CasADi call:
        (guesses (1 x n each), p (len(p) x n)) -> each output (1 x n), then each output's
        d / d p (len(p) x n, implicit function theorem), then the largest normalised residual at
        the roots (1 x n: near 0 where Newton converged). Built once per (name, n)."""
        if (name, n) in self._batches:
            return self._batches[name, n]
        if name not in self._batches:
            F, sy = self.functions[name], self.symbols
            k = F.n_in() - 1                              # the unknowns: the first k outputs
            g = [ca.MX.sym(F.name_in(i)) for i in range(k)]
            p = ca.MX.sym("p", sy.p.numel())
            y = F(*g, p)
            y = list(y) if isinstance(y, tuple) else [y]
            v = ca.SX.sym("v", k)
            res = ca.Function(f"{name}_check", [v, sy.p],
                              [ca.mmax(ca.fabs(ca.vertcat(*RESIDUALS[name](sy, v))))])
            outs = [*y, *[ca.jacobian(yi, p).T for yi in y], res(ca.vertcat(*y[:k]), p)]
            self._batches[name] = ca.Function(f"{name}_batch", [*g, p], outs)
        self._batches[name, n] = self._batches[name].map(n)
        return self._batches[name, n]

    def outputs(self) -> list[str]:
        """The names of every quantity the Functions give (z_s, stiffness, sigma_lo, ...)."""
        return [n for F in self.functions.values() for n in F.name_out()]
