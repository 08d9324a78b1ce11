"""Route "eigenvalues" of the linear stability analysis (thesis 3.3.4-3.3.5).

The Jacobian of the full model at the relative equilibrium (the generated `full_jac`, or
`transverse_matrix` below, the 8-D system after thesis 3.3.5), its eigenvalues, and the spin
interval where they all lie on the imaginary axis; "on the axis" is decided with a first-order
perturbation bound (see `on_imaginary_axis`). No sympy here.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

EPS = np.finfo(float).eps

TRANSVERSE_STATES = ("x", "y", "vartheta", "phi", "p_x", "p_y", "p_vartheta", "p_phi")


def transverse_matrix(phi1: float, phi2: float, phi3: float, m: float, A: float, C: float,
                      mu: float, sigma: float) -> np.ndarray:
    """The 8-D linear system after thesis 3.3.5 (rows/columns TRANSVERSE_STATES), as derived in
    tests/helpers/stability_derivation.py (linear_system_8d; a test checks the two agree). p_zeta = C sigma."""
    pz = C * sigma
    J = np.zeros((8, 8))
    J[0, 4] = J[1, 5] = 1 / m
    J[2, 6] = 1 / A
    J[3, 2], J[3, 7] = -pz / A, 1 / A
    J[4, 0], J[4, 2] = mu * phi3 / 2, mu * phi2 / 2
    J[5, 1], J[5, 3] = mu * phi3 / 2, mu * phi2 / 2
    J[6, 0], J[6, 2], J[6, 7] = mu * phi2 / 2, mu * phi1 - pz ** 2 / A, pz / A
    J[7, 1], J[7, 3] = mu * phi2 / 2, mu * phi1
    return J


def full_equilibrium_state(states: Sequence[str], z_s: float, C: float, sigma: float) -> np.ndarray:
    """The relative equilibrium (thesis 3.3.4, 3.3.5) as a full Tait-Bryan state vector."""
    x = np.zeros(len(states))
    x[list(states).index("z")] = z_s
    x[list(states).index("p_zeta")] = C * sigma
    return x


def transverse_block(J: np.ndarray, states: Sequence[str]) -> np.ndarray:
    """The 8x8 transverse block of a full 12x12 Jacobian, after checking that it decouples from
    (z, zeta, p_z, p_zeta) as the axial symmetry demands (coupling below 12 eps ||J||_F)."""
    idx = [list(states).index(s) for s in TRANSVERSE_STATES]
    rest = [i for i in range(len(states)) if i not in idx]
    bound = len(states) * EPS * np.linalg.norm(J)
    coupling = max(np.abs(J[np.ix_(idx, rest)]).max(), np.abs(J[np.ix_(rest, idx)]).max())
    if coupling > bound:
        raise ValueError(f"the transverse block does not decouple (coupling {coupling:.3g} > {bound:.3g}):"
                         " the state is not a relative equilibrium on the axis")
    return J[np.ix_(idx, idx)]


@dataclass(frozen=True)
class EigenCheck:
    eigenvalues: np.ndarray
    tolerance: np.ndarray       # per eigenvalue: how far from the axis rounding alone can put it
    stable: bool



SCLFAC, FACTOR = 2.0, 0.95                       # LAPACK dgebal's constants
SFMIN1 = np.finfo(float).tiny / (np.finfo(float).eps / 2)    # dlamch('S') / dlamch('P')
SFMAX1, SFMIN2 = 1.0 / SFMIN1, SFMIN1 * SCLFAC
SFMAX2 = 1.0 / SFMIN2


def balancing(J: np.ndarray) -> np.ndarray:
    """Diagonal scaling d (powers of 2) with D^-1 J D balanced, reusable for nearby J: LAPACK 3.12's
    dgebal with job 'S' (scale, no permutation), what scipy.linalg.matrix_balance(J, permute=False)
    calls, written out here because importing scipy.linalg is a third of `levitron stability`'s
    start-up. tests/runtime/physics/routes/test_balance.py checks d against scipy's. Any d keeps on_imaginary_axis's
    bound
    valid; this one makes it tight."""
    A = np.array(J, dtype=float)
    n = A.shape[0]
    scale = np.ones(n)
    noconv = True
    while noconv:
        noconv = False
        for i in range(n):
            c, r = float(np.sqrt(A[:, i] @ A[:, i])), float(np.sqrt(A[i, :] @ A[i, :]))
            ca, ra = float(np.max(np.abs(A[:, i]))), float(np.max(np.abs(A[i, :])))
            if c == 0.0 or r == 0.0:
                continue
            if not np.isfinite(c + ca + r + ra):
                raise ValueError("balancing: the matrix has a NaN or an infinite entry")
            g, f, s = r / SCLFAC, 1.0, c + r
            while c < g and max(f, c, ca) < SFMAX2 and min(r, g, ra) > SFMIN2:
                f, c, ca, r, g, ra = f * SCLFAC, c * SCLFAC, ca * SCLFAC, r / SCLFAC, g / SCLFAC, ra / SCLFAC
            g = c / SCLFAC
            while g >= r and max(r, ra) < SFMAX2 and min(f, c, g, ca) > SFMIN2:
                f, c, g, ca, r, ra = f / SCLFAC, c / SCLFAC, g / SCLFAC, ca / SCLFAC, r * SCLFAC, ra * SCLFAC
            if c + r >= FACTOR * s:
                continue
            if f < 1.0 and scale[i] < 1.0 and f * scale[i] <= SFMIN1:
                continue
            if f > 1.0 and scale[i] > 1.0 and scale[i] >= SFMAX1 / f:
                continue
            scale[i] *= f
            noconv = True
            A[i, :] *= 1.0 / f
            A[:, i] *= f
    return scale


def on_imaginary_axis(J: np.ndarray, d: np.ndarray | None = None) -> EigenCheck:
    """Eigenvalues of J and whether all lie on the imaginary axis, up to rounding.

    The tolerance is a first-order perturbation bound, no magic number: the matrix is balanced,
    Jb = D^-1 J D with D a diagonal of powers of 2 (exact in binary floating point; LAPACK's geev
    does the same), and a backward stable eigensolver returns the exact eigenvalues of Jb + E with
    ||E||_F <= n eps ||Jb||_F; the entries of J carry one more rounding each (<= eps ||Jb||_F in
    all); the eigenvector matrix is inverted in floating point too, which only perturbs the
    condition numbers, not the eigenvalues. So |delta lambda_i| <= kappa_i (n + 1) eps ||Jb||_F with
    kappa_i = ||x_i|| ||y_i|| / |y_i^H x_i| the condition number of lambda_i (x_i right, y_i^H the
    rows of X^-1, the left eigenvectors). An eigenvalue is on the axis if |Re lambda_i| is within it.
    `d` may be passed (from `balancing`) to reuse one scaling along a scan; any diagonal scaling
    keeps the bound valid because norm and kappa are taken of the matrix actually solved.
    """
    if d is None:
        d = balancing(J)
    Jb = J * np.outer(1.0 / d, d)
    w, X = np.linalg.eig(Jb)
    Yh = np.linalg.inv(X)
    kappa = np.linalg.norm(X, axis=0) * np.linalg.norm(Yh, axis=1)  # |y^H x| = 1 by construction
    n = J.shape[0]
    tol = kappa * (n + 1) * EPS * np.linalg.norm(Jb)
    return EigenCheck(w, tol, bool(np.all(np.abs(w.real) <= tol)))


def spin_intervals_eigen(jac: Callable[[float], np.ndarray], sigma_scale: float,
                         extra_probes: Sequence[float] = (), decades: tuple[float, float] = (-3, 4),
                         per_decade: int = 8, rtol: float = 1e-11) -> list[tuple[float, float]]:
    """Spin intervals where on_imaginary_axis(jac(sigma)) holds (route "eigenvalues").

    sigma is scanned on a log grid sigma_scale * 10^[decades] (sigma_scale: a natural rate of the
    scene, e.g. sqrt(|mu Phi1| / A) / rho), plus `extra_probes` (e.g. the midpoints found by the
    other route, so that an interval narrower than the grid is not missed); every change of the
    verdict is then bisected to rtol relative.
    """
    grid = sigma_scale * np.logspace(decades[0], decades[1], int((decades[1] - decades[0]) * per_decade) + 1)
    grid = np.unique(np.concatenate([grid, np.asarray(extra_probes, float)]))
    grid = grid[grid > 0]
    d = balancing(jac(float(np.sqrt(grid[0] * grid[-1]))))
    verdict = [on_imaginary_axis(jac(s), d).stable for s in grid]

    def refine(a: float, b: float, va: bool) -> float:
        while b - a > rtol * b:
            mid = math.sqrt(a * b)
            if on_imaginary_axis(jac(mid), d).stable == va:
                a = mid
            else:
                b = mid
        return math.sqrt(a * b)

    out = []
    lo = None
    for i, (s, v) in enumerate(zip(grid, verdict)):
        if v and lo is None:
            lo = 0.0 if i == 0 else refine(grid[i - 1], s, False)
        if not v and lo is not None:
            out.append((lo, refine(grid[i - 1], s, True)))
            lo = None
    if lo is not None:
        out.append((lo, math.inf))
    return out


def growth_rate(J: np.ndarray) -> float:
    """The largest real part of the eigenvalues of J (the e-folding rate of the fastest mode)."""
    return float(np.max(np.linalg.eigvals(J).real))

