"""The root search of the equilibrium finder (runtime/physics/equilibrium/finder.py, thesis 3.3.2-3.3.3):
the zeros of F(z) = m g + mu Phi_2(z) and of Phi_3 on z > 0, from the plate's on-axis functions alone.

How the roots are found, however close (every command uses this; no other z grid for roots):
  * The on-axis functions Phi_k = d^k Phi_0 / dz^k are sampled on a log grid of heights that scales
    with one length of the scene (`scale_of`), and the stretches where they are NaN or infinite are
    cut out; their edges are located by bisection and reported as `singularities`, never searched
    across, so a NaN stretch hides no root elsewhere.
  * The zeros of Phi_k are then found level by level, from k = min(K, 4) down to 2: between
    consecutive zeros of Phi_{k+1}, Phi_k is monotone and has at most one zero, so every sign change
    of Phi_k between consecutive knots (grid points and zeros of Phi_{k+1}) brackets exactly one.
    The zeros of Phi_3 are the extrema of F; so two roots of F, however close, lie on either side
    of the zero of Phi_3 between them, and each is bracketed alone.
  * A bracket is refined by bisection to adjacent doubles. A sign change across a pole is not a
    zero: the result is a zero only where |Phi_k| has shrunk below its values at the bracket's ends;
    otherwise it is a pole, reported and cut out like a NaN stretch.
  * A mass equal to the maximum is a double root at z_c: where |F(z_e)| at a zero z_e of Phi_3 is
    within rounding of F's terms (16 eps (|m g| + |mu Phi_2|)), ONE equilibrium is reported there,
    flagged `marginal` (and not vertically stable, U'' = 0).
All lengths scale with the `scale` given (the plate's size), never a fixed number: scenes may be
dimensionless. The heights searched are scale * [1e-4, 1e4]. No sympy here.
"""
from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium.report import Equilibrium, EquilibriumReport, Singularity

OnAxis = Callable[[float], Sequence[float]]  # z -> [Phi_0, Phi_1, ..., Phi_K], K >= 3

EPS = float(np.finfo(float).eps)
GRID_DECADES = (-4.0, 4.0)   # heights scale * 10^[-4, 4]
GRID_PER_DECADE = 64
SPAN_POINTS = 64             # at least this many grid cells across a stated plate.z_range
MARGINAL_ULPS = 16           # a double root: |F(z_c)| <= 16 eps (|m g| + |mu Phi_2(z_c)|)


# ------------------------------------------------------------------------ the search

class NonFiniteModel(UserError):
    """The plate's on-axis functions are NaN or infinite at every sampled height."""


def z_grid(scale: float, span: tuple[float, float] | None = None) -> np.ndarray:
    """The log grid of heights scale * 10^[-4, 4], GRID_PER_DECADE points a decade; with a span
    (lo, hi) (a formula's plate.z_range) the same density from lo to hi, at least SPAN_POINTS."""
    if span is not None:
        lo, hi = span
        return np.geomspace(lo, hi, max(round(math.log10(hi / lo) * GRID_PER_DECADE), SPAN_POINTS) + 1)
    lo, hi = GRID_DECADES
    return scale * np.logspace(lo, hi, round((hi - lo) * GRID_PER_DECADE) + 1)


def _row(onaxis: OnAxis, z: float, ncol: int) -> np.ndarray:
    """[Phi_0..Phi_{ncol-1}](z); NaN where a (Python) formula cannot be evaluated."""
    try:
        v = np.asarray(onaxis(float(z)), float)[:ncol]
    except (ArithmeticError, ValueError):
        v = np.full(ncol, math.nan)
    return v


def _width(onaxis: OnAxis, zs: Sequence[float]) -> int:
    """K + 1, the number of on-axis functions (Phi_0..Phi_K) the plate's onaxis returns."""
    for z in zs:
        try:
            return int(np.asarray(onaxis(float(z)), float).size)
        except (ArithmeticError, ValueError):
            continue
    raise UserError("the plate's on-axis functions cannot be evaluated at any height z > 0")


def _bisect(f: Callable[[float], float], a: float, b: float, fa: float, fb: float):
    """Narrow the bracket [a, b] of a sign change of f (fa fb < 0) to adjacent doubles.
    Returns (a, b, fa, fb), or (z, z, v, v) where f(z) is 0 or not finite."""
    while True:
        mid = 0.5 * (a + b)
        if not a < mid < b:
            return a, b, fa, fb
        fm = f(mid)
        if fm == 0 or not math.isfinite(fm):
            return mid, mid, fm, fm
        if (fm < 0) == (fa < 0):
            a, fa = mid, fm
        else:
            b, fb = mid, fm


def _edge(finite: Callable[[float], bool], a: float, b: float) -> tuple[float, float]:
    """The edge between a (finite) and b (not finite), to adjacent doubles: (last finite, first not)."""
    while True:
        mid = 0.5 * (a + b)
        if not (min(a, b) < mid < max(a, b)):
            return a, b
        if finite(mid):
            a = mid
        else:
            b = mid


@dataclass
class Survey:
    """The on-axis functions of one plate on z > 0, independent of the top (thesis 3.3.2-3.3.3):
    knots (sorted heights with their rows [Phi_0..Phi_top]), the singular stretches, and the zeros of
    Phi_3 (the extrema of F for every mass). Make one with `survey`."""
    onaxis: OnAxis
    scale: float
    top: int                              # the highest derivative used, min(K, 4)
    zs: list[float]                       # knots, sorted
    rows: dict[float, np.ndarray]         # knot -> [Phi_0..Phi_top]
    singularities: list[Singularity]
    barriers: list[tuple[float, float]]   # (last finite below, first finite above) of each singularity
    extrema: list[float]                  # zeros of Phi_3, sorted
    columns: dict[int, np.ndarray] = field(default_factory=dict)   # column(k), while the knots stand

    # ---- building blocks
    def row(self, z: float) -> np.ndarray:
        r = self.rows.get(z)
        return _row(self.onaxis, z, self.top + 1) if r is None else r

    def _add_knot(self, z: float, r: np.ndarray | None = None) -> None:
        if z not in self.rows:
            self.rows[z] = self.row(z) if r is None else r
            bisect.insort(self.zs, z)
            self.columns.clear()

    def column(self, k: int) -> np.ndarray:
        """Phi_k at the knots, in their order (kept until a knot is added; a copy to write on)."""
        if k not in self.columns:
            self.columns[k] = np.array([float(self.rows[z][k]) for z in self.zs])
        return self.columns[k].copy()

    def _blocked(self, a: float, b: float) -> bool:
        return any(a < hi and b > lo for lo, hi in self.barriers)

    def _finite(self, z: float) -> bool:
        return bool(np.all(np.isfinite(_row(self.onaxis, z, self.top + 1)[2:])))

    def _add_pole(self, a: float, b: float) -> None:
        """A sign change across a pole between the adjacent doubles a < b (both finite)."""
        self._cut(a, 0.5 * (a + b), 0.5 * (a + b), b, "pole")

    def _cut(self, lo_ok: float, lo_bad: float, hi_bad: float, hi_ok: float, kind: str | None = None):
        """Cut out the singular stretch [lo_bad, hi_bad] between the finite heights lo_ok < hi_ok
        (0 / inf: it reaches the end of the search): locate its edges, record it, block searches
        across it and add its finite edges as knots."""
        if lo_ok > 0:
            lo_ok, lo_bad = _edge(self._finite, lo_ok, lo_bad)
        if hi_ok < math.inf:
            hi_ok, hi_bad = _edge(self._finite, hi_ok, hi_bad)
        if kind is None:
            point = hi_bad - lo_bad <= 4 * EPS * hi_bad and lo_ok > 0 and hi_ok < math.inf
            probes = [_row(self.onaxis, z, self.top + 1)[2:] for z in (lo_bad, 0.5 * (lo_bad + hi_bad), hi_bad)]
            kind = "pole" if point else ("nan" if any(np.isnan(r).any() for r in probes) else "inf")
        if kind == "pole":
            z = 0.5 * (lo_bad + hi_bad)
            sing = Singularity(z, z, kind)
        else:
            sing = Singularity(lo_bad if lo_ok > 0 else 0.0, hi_bad if hi_ok < math.inf else math.inf, kind)
        if not any(s.z <= sing.z_end and sing.z <= s.z_end for s in self.singularities):
            self.singularities.append(sing)
        self.barriers.append((lo_ok, hi_ok))
        for z in (lo_ok, hi_ok):
            if 0 < z < math.inf and self._finite(z):
                self._add_knot(z)

    def zeros(self, value: Callable[[float, np.ndarray], float],
              vals: np.ndarray | None = None) -> list[float]:
        """Every zero of value(z, row) between consecutive knots (sign changes and exact zeros),
        refined to adjacent doubles; a sign change across a pole or a non-finite sliver is recorded
        as a singularity and cut out instead. vals: value at the knots, if the caller has them
        (equilibria: one array operation, the same doubles)."""
        zs = list(self.zs)
        vals = np.array([value(z, self.rows[z]) for z in zs] if vals is None else vals, float)
        # only knots that are exact zeros or open a sign change can give a zero: visit those alone
        visit = np.flatnonzero((vals == 0) | np.append(vals[:-1] * vals[1:] < 0, False))
        out = []
        for i in visit.tolist():
            z, v = zs[i], float(vals[i])
            if v == 0 and not any(lo < z < hi for lo, hi in self.barriers):
                out.append(z)
            if i + 1 == len(zs):
                break
            z1, v1 = zs[i + 1], float(vals[i + 1])
            if not (v * v1 < 0) or self._blocked(z, z1):
                continue
            f = lambda x: value(x, self.row(x))
            a, b, fa, fb = _bisect(f, z, z1, v, v1)
            if a == b and not math.isfinite(fa):          # a NaN or inf sliver inside the bracket
                self._cut(z, a, a, z1)
                continue
            best, fbest = (a, fa) if abs(fa) <= abs(fb) else (b, fb)
            if abs(fbest) <= max(abs(v), abs(v1)):
                out.append(best)
            else:                                          # |value| grew: a pole, not a zero
                self._add_pole(a, b)
        return sorted(set(out))

    # ---- per top
    def critical(self, g: float, mu: float) -> tuple[float | None, float | None]:
        """(z_c, max_mass): the zero of Phi_3 at which m(z) = -mu Phi_2/g (dm/dz = -mu Phi_3/g) is
        largest and positive, and m(z_c); (None, None) when m(z) has no such maximum on z > 0 (the
        field never holds a top, or m(z) grows towards a singularity or the end of the search)."""
        cands = [(-mu * float(self.row(z)[2]) / g, z) for z in self.extrema]
        cands = [(m, z) for m, z in cands if m > 0 and math.isfinite(m)]
        if not cands:
            return None, None
        m_c, z_c = max(cands)
        return z_c, m_c

    def equilibria(self, m: float, g: float, mu: float) -> list[Equilibrium]:
        """All roots of F(z) = m g + mu Phi_2(z) on z > 0 (thesis 3.3.2), each marked vertically
        stable where mu Phi_3 > 0 (3.3.3); a double root at a zero of Phi_3 is one marginal root."""
        mg = m * g
        marginal = set()
        for z in self.extrema:
            mp2 = mu * self.row(z)[2]
            if abs(mg + mp2) <= MARGINAL_ULPS * EPS * (abs(mg) + abs(mp2)):
                marginal.add(z)

        def F(z: float, r: np.ndarray) -> float:
            return 0.0 if z in marginal else mg + mu * float(r[2])

        vals = mg + mu * self.column(2)         # F at the knots (the doubles F gives, at once)
        for k, z in enumerate(self.zs):
            if z in marginal:
                vals[k] = 0.0
        out = []
        for z in self.zeros(F, vals):
            if z in marginal:
                out.append(Equilibrium(z, False, mu * float(self.row(z)[3]), True))
            else:
                k = mu * float(self.row(z)[3])
                out.append(Equilibrium(z, k > 0, k))
        return out

    def report(self, m: float, g: float, mu: float) -> EquilibriumReport:
        eqs = self.equilibria(m, g, mu)
        z_c, max_mass = self.critical(g, mu)
        return EquilibriumReport(eqs, z_c, max_mass, sorted(self.singularities, key=lambda s: s.z))


def survey(onaxis: OnAxis, scale: float, span: tuple[float, float] | None = None) -> Survey:
    """Sample the plate's on-axis functions, cut out their singular stretches, and find the zeros of
    Phi_top .. Phi_3 level by level (see the module docstring; thesis 3.3.2-3.3.3); only inside
    span where a formula states where it holds (runtime/physics/equilibrium/finder.py span_of)."""
    if not (scale > 0 and math.isfinite(scale)):
        raise UserError(f"the scene's length scale {scale} must be a positive number")
    zs = [float(z) for z in z_grid(scale, span)]
    width = _width(onaxis, zs)
    if width < 4:
        raise UserError(f"the model's onaxis gives Phi_0..Phi_{width - 1}: the equilibrium search "
                        "needs Phi_3 at least (re-derive with a higher field.order)")
    top = min(width, 5) - 1
    rows = {z: _row(onaxis, z, top + 1) for z in zs}
    good = [bool(np.all(np.isfinite(rows[z][2:]))) for z in zs]
    # the potential itself not finite where its derivatives are: a formula that is 1/0 (b z /
    # (sin^2 z + cos^2 z - 1)) whose derivatives came out finite (0), no field to stand on
    bare = sum(1 for z, ok in zip(zs, good) if ok and not np.isfinite(rows[z][0]))
    if bare > sum(good) / 2:
        raise NonFiniteModel(f"the on-axis potential Phi_0 is not finite (NaN or inf) at {bare} of the "
                             f"{sum(good)} heights from {zs[0]:.3g} to {zs[-1]:.3g} where its derivatives "
                             "are (a formula that divides by zero?): no physical potential")
    if not any(good):
        raise NonFiniteModel(f"the on-axis functions Phi_2..Phi_{top} are not finite (NaN or inf) at "
                             f"any height from {zs[0]:.3g} to {zs[-1]:.3g}: no physical potential")
    s = Survey(onaxis, scale, top, [], {}, [], [], [])
    for z, ok in zip(zs, good):
        if ok:
            s._add_knot(z, rows[z])
    i, n = 0, len(zs)
    while i < n:
        if good[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and not good[j + 1]:
            j += 1
        s._cut(zs[i - 1] if i > 0 else 0.0, zs[i], zs[j], zs[j + 1] if j + 1 < n else math.inf)
        i = j + 1
    for k in range(top, 2, -1):
        zk = s.zeros(lambda z, r, k=k: float(r[k]))
        for z in zk:
            s._add_knot(z)
        if k == 3:
            s.extrema = zk
    return s
