"""What a run conserves, evaluated over its samples: the energy H, L_z and L.n (Noether; the
generated `full_energy` and `full_invariants`, derive/invariants.py, in one C call per run through
Model.rows), the tilt of the axis (`full_axis`), and their largest deviations. The numpy routes
(angular_momentum_z: the rotation generator of rotations.py by least squares) are the second
route the tests compare with."""
from __future__ import annotations

import numpy as np

from dataclasses import dataclass

from levitron.runtime.simulate.rotations import ANGLES, angle_generator_z, coordinates_of, rotation_bs


def tilt_of(part, X: np.ndarray) -> np.ndarray:
    """Angle between the symmetry axis n = R_bs e_z and the vertical, for each state row."""
    coords = coordinates_of(part)
    X = np.atleast_2d(X)
    if coords is None:
        return np.zeros(len(X))
    if getattr(part, "model", None) is not None and part.has("axis"):
        nz = part.model.rows(f"{part.name}_axis", X)[:, 2]     # the generated n, one C call
    else:
        idx = [part.states.index(a) for a in ANGLES[coords]]
        nz = np.array([rotation_bs(coords, row[idx])[2, 2] for row in X])
    return np.arccos(np.clip(nz, -1.0, 1.0))


def angular_momentum_z(part, x: np.ndarray) -> float:
    """L_z = x p_y - y p_x + sum_a p_a (d a / d alpha): conserved by the axially symmetric field."""
    s = list(part.states)
    coords = coordinates_of(part)
    if coords is None:   # reduced model: the top spins about the vertical; zeta is a -z rotation
        return -float(x[s.index("p_zeta")]) if "p_zeta" in s else float("nan")
    lz = x[s.index("x")] * x[s.index("p_y")] - x[s.index("y")] * x[s.index("p_x")]
    names = ANGLES[coords]
    gen = angle_generator_z(coords, [x[s.index(a)] for a in names])
    return float(lz + sum(gen[i] * x[s.index("p_" + a)] for i, a in enumerate(names)))


def spin_momentum(part, x) -> float:
    """L.n, the angular momentum about the symmetry axis: -p_zeta (Tait-Bryan, where
    p_zeta = -C omega_3, thesis 3.2.9) or p_psi (z-x-z, thesis 2.1.10); NaN if neither."""
    s = list(part.states)
    if "p_zeta" in s:
        return -float(x[s.index("p_zeta")])
    if "p_psi" in s:
        return float(x[s.index("p_psi")])
    return float("nan")


def spin_rate(part, X, C: float, p=None) -> np.ndarray:
    """omega_3 = L.n / C along the state rows X (invariants)."""
    return invariants(part, X, p)[:, 1] / C


def largest_deviation(values, scale: float) -> float | None:
    """max_t |v(t) - v(0)| / scale (None if undefined): an invariant's worst drift over the run."""
    v = np.asarray(values, float)
    if not len(v) or not np.all(np.isfinite(v)) or not scale > 0:
        return None
    return float(np.abs(v - v[0]).max() / scale)


def rows_of(pt, kind: str, X, p) -> np.ndarray:
    """The part's generated function `kind` at every row of X, in one C call (Model.rows)."""
    model = getattr(pt, "model", None)
    if model is not None and pt.has(kind):
        return model.rows(f"{pt.name}_{kind}", X, p)
    f = getattr(pt, kind)
    return np.array([np.atleast_1d(f(x, p)) for x in np.atleast_2d(X)])


def invariants(pt, X, p) -> np.ndarray:
    """(L_z, L.n) at every row of X: the generated `full_invariants` (derive/invariants.py) in one
    C call; the reduced model (on the invariant set, spinning about the vertical) has
    L_z = L.n = -p_zeta; a part without either: the numpy routes angular_momentum_z/spin_momentum."""
    X = np.atleast_2d(X)
    model = getattr(pt, "model", None)
    if model is not None and pt.has("invariants"):
        return model.rows(f"{pt.name}_invariants", X, p)
    if coordinates_of(pt) is None and "p_zeta" in pt.states:   # the reduced model: a column
        lz = -X[:, list(pt.states).index("p_zeta")].astype(float)
        return np.column_stack([lz, lz])
    return np.array([[angular_momentum_z(pt, x), spin_momentum(pt, x)] for x in X])


def deviations(pt, X, x0, p, pv: dict, spin: float, energy: float, inv=None) -> dict:
    """The largest relative deviation over the samples of H (given), L_z and L.n, each relative to
    max(|its start value|, C |spin|) (the spin's angular momentum: the scale of both). inv: the
    invariants of x0 then the rows of X, if already computed (Samples)."""
    c_spin = pv.get("C", 0.0) * abs(spin)
    if inv is None:
        inv = invariants(pt, np.vstack([x0, X]), p)
    lz, ln = inv[:, 0], inv[:, 1]
    return {"energy": energy,
            "L_z": largest_deviation(lz, max(abs(lz[0]), c_spin)),
            "L_n": largest_deviation(ln, max(abs(ln[0]), c_spin))}


@dataclass(frozen=True)
class Samples:
    """A run's per-sample quantities, each computed once for its summary and its trajectory table:
    the energy H at the samples (the integrator's own where it monitored it), the invariants
    (L_z, L.n) of the start x0, the samples, then the final state, and the tilt at the samples."""
    energy: np.ndarray
    invariants: np.ndarray
    tilt: np.ndarray

    @classmethod
    def of(cls, pt, res, x0, p) -> Samples:
        X = np.atleast_2d(res.X)
        H = res.energy if res.energy is not None else rows_of(pt, "energy", X, p)[:, 0]
        inv = invariants(pt, np.vstack([x0, X, res.x_final]), p)     # one C call
        return cls(np.asarray(H, float), inv, tilt_of(pt, X))
