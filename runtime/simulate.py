"""One trajectory of the top from its stable hover height (docs/contract.md `simulate`; thesis 3.1-3.3).

The initial state: the centre of mass at (offset, 0, z_s), where z_s is the vertically stable root
of m g + mu Phi_2(z) = 0 (thesis eqs. 3.3.2-3.3.3, from runtime.equilibrium); the symmetry axis
n tilted by `tilt` rad towards the azimuth `azimuth` (rad from +x towards +y; default pi/2, i.e.
towards +y), n = (sin tilt cos az, sin tilt sin az, cos tilt) (Tait-Bryan angles of thesis 3.2.2:
vartheta = asin(sin tilt cos az), phi = atan2(sin tilt sin az, cos tilt); z-x-z Euler angles of
2.1.9: phi = az + pi/2, theta = tilt); at rest except
for the spin: angular velocity omega = spin * n, i.e. a right-handed spin of `spin` rad/s about n
(zeta_dot = -spin in Tait-Bryan angles, where omega_3 = -(zeta_dot + phi_dot sin vartheta),
thesis 3.2.9; psi_dot = +spin in z-x-z angles, 2.1.10). The momenta are built from these
velocities through the model's own Legendre map: the coordinate rows of the generated rhs are
dq/dt = M(q)^-1 p (thesis eq. 2.3.8), linear in p, so p = M(q) qdot is solved from that map.
With Tait-Bryan angles this gives p_zeta = C (zeta_dot + phi_dot sin vartheta) = -C omega_3.

The default launch is perturbed: a launch with tilt 0 and offset 0 lies exactly on the invariant
set I (thesis 3.2.1), where the ideal top stays at any spin, so it tests no stability. Without a
given tilt the axis starts DEFAULT_TILT rad from the vertical (Gans et al. perturb by 0.001-0.005
rad); a launch given exactly on I is run but answers `levitating: null` with the reason.

With air friction (a scene with decay times, derive/friction.py) the run goes on until the top
falls or t_end (default FRICTION_T_END_TAUS spin decay times), and the answer carries a `flight`
block (runtime/flight.py): the flight time, the spin at which the top fell and the adiabatic
prediction tau ln(omega_0 / sigma_lo).

The run stops when the top leaves a box that scales with the hover height (default half-width
z_s / 2 in z and radially; scenes may be dimensionless, so never a fixed length).

Conserved quantities (Noether): the energy H (thesis 2.3.9 / 3.2.11), p_zeta (zeta is cyclic) and
the z-component of the total angular momentum L_z = x p_y - y p_x + sum_a p_a d a/d alpha, where
d a/d alpha is the change of the angles under a rotation of the whole top by alpha about the lab z
axis (R_bs -> Q_z(alpha) R_bs), computed here from the rotation matrices of derive/kinematics.py.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from runtime.equilibrium import hover_height
from runtime.errors import UserError
from runtime.validate import count, real
from runtime.integrate import Box, Result, integrate
from runtime.integrators_table import AUTO, DEFAULT, auto_note, lookup, resolve

from . import flight, trajectory_file
from .human import Units, sig
from .stability import stability_of
from .plotting import pyplot, save_figure, style

# ---------------------------------------------------------------- rotations (numpy mirrors of
# derive/kinematics.py: passive elementary matrices of thesis eqs. 2.1.6-2.1.8 and 3.2.3-3.2.5)

def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, s], [0, -s, c]])


def _ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])


ANGLES = {"tait-bryan": ("phi", "vartheta", "zeta"), "euler-zxz": ("phi", "theta", "psi")}
SPIN_ANGLE = {"tait-bryan": "zeta", "euler-zxz": "psi"}
TILT_ANGLE = {"tait-bryan": "phi", "euler-zxz": "theta"}


def coordinates_of(part) -> str | None:
    """"tait-bryan", "euler-zxz" (full models) or None (the reduced model)."""
    names = set(part.states)
    for name, angles in ANGLES.items():
        if set(angles) <= names:
            return name
    return None


def _drx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[0, 0, 0], [0, -s, c], [0, -c, -s]])


def _dry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[-s, 0, c], [0, 0, 0], [-c, 0, -s]])


def _drz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[-s, c, 0], [-c, -s, 0], [0, 0, 0]])


def _factors(coords: str, angles: Sequence[float]):
    """R_bs as a product of three elementary matrices (and their derivatives), in order."""
    a, b, c = angles
    if coords == "tait-bryan":       # Rx(phi) Ry(vartheta) Rz(zeta)
        return [(_rx(a), _drx(a)), (_ry(b), _dry(b)), (_rz(c), _drz(c))]
    # (R3(psi) R2(theta) R1(phi))^T = R1(phi)^T R2(theta)^T R3(psi)^T
    return [(_rz(a).T, _drz(a).T), (_rx(b).T, _drx(b).T), (_rz(c).T, _drz(c).T)]


def rotation_bs(coords: str, angles: Sequence[float]) -> np.ndarray:
    """Body -> space rotation: Rx(phi) Ry(vartheta) Rz(zeta) (thesis 3.2.2), or
    (R3(psi) R2(theta) R1(phi))^T (thesis 2.1.9)."""
    f = _factors(coords, angles)
    return f[0][0] @ f[1][0] @ f[2][0]


def rotation_bs_derivatives(coords: str, angles: Sequence[float]) -> list[np.ndarray]:
    """d R_bs / d angle_i, analytic (product rule)."""
    f = _factors(coords, angles)
    return [f[0][1] @ f[1][0] @ f[2][0], f[0][0] @ f[1][1] @ f[2][0], f[0][0] @ f[1][0] @ f[2][1]]


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


def angle_generator_z(coords: str, angles: Sequence[float]) -> np.ndarray:
    """d angles / d alpha under R_bs -> Q_z(alpha) R_bs (active rotation about the lab z axis):
    least squares of dR = sum_i dR/da_i da_i = K R, K = [[0,-1,0],[1,0,0],[0,0,0]]."""
    ang = np.asarray(angles, float)
    R = rotation_bs(coords, ang)
    K = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    cols = [d.ravel() for d in rotation_bs_derivatives(coords, ang)]
    sol, *_ = np.linalg.lstsq(np.array(cols).T, (K @ R).ravel(), rcond=None)
    return sol


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


# ---------------------------------------------------------------- initial state

def coordinate_names(part) -> list[str]:
    return [s for s in part.states if not s.startswith("p_")]


def legendre_map(part, q: np.ndarray, p=None) -> tuple[np.ndarray, np.ndarray]:
    """The coordinate rows of the generated rhs at coordinates q, dq/dt = M(q)^-1 p_q (thesis eq.
    2.3.8), linear in the momenta: (f0, Minv), f0 the rows at p_q = 0 and Minv's column k the rows
    at p_k = 1 less f0."""
    s = list(part.states)
    coords = coordinate_names(part)
    ic = [s.index(c) for c in coords]
    ip = [s.index("p_" + c) for c in coords]
    base = np.zeros(len(s))
    base[ic] = q
    f0 = part.rhs(base, p)[ic]
    cols = []
    for k in ip:
        e = base.copy()
        e[k] = 1.0
        cols.append(part.rhs(e, p)[ic] - f0)
    return f0, np.array(cols).T


DEFAULT_AZIMUTH = math.pi / 2    # the tilt towards +y
DEFAULT_TILT = 0.005             # rad: the default launch's tilt (module docstring)
FRICTION_T_END_TAUS = 5.0        # default run length with friction: 5 tau, the spin falls by e^5


def on_invariant_set(part, tilt: float, offset: float) -> bool:
    """A full-model launch with tilt 0 and offset 0: on I (thesis 3.2.1), where it tests nothing."""
    return coordinates_of(part) is not None and tilt == 0.0 and offset == 0.0


UNTESTED = ("the launch lies on the invariant set (tilt 0, offset 0; thesis 3.2.1), where the ideal "
            "top stays at any spin: this run tests no stability; give a tilt (e.g. --tilt "
            f"{DEFAULT_TILT}) or an offset")


def tilt_angles(kind: str, tilt: float, azimuth: float = DEFAULT_AZIMUTH) -> list[float]:
    """The three angles whose body axis is n = (sin tilt cos az, sin tilt sin az, cos tilt), with
    no rotation about n (module docstring)."""
    if kind == "tait-bryan":     # n = (sin vartheta, sin phi cos vartheta, cos phi cos vartheta)
        return [math.atan2(math.sin(tilt) * math.sin(azimuth), math.cos(tilt)),
                math.asin(math.sin(tilt) * math.cos(azimuth)), 0.0]
    return [azimuth + math.pi / 2, tilt, 0.0]    # n = (sin phi sin theta, -cos phi sin theta, cos theta)


@dataclass(frozen=True)
class Launch:
    """The spin-free part of the initial state (module docstring): the coordinates q, the Legendre
    map at q (legendre_map: f0, Minv) and the spin angle's rate per unit spin, 1 / along. A map
    (runtime/scan_runners.py) computes it once per launch position and tilt for all its spins."""
    q: np.ndarray
    f0: np.ndarray
    Minv: np.ndarray
    i_spin: int          # the spin angle's index among the coordinates
    along: float         # omega . n per unit rate of the spin angle: +1 or -1
    ic: list             # the state indices of the coordinates ...
    ip: list             # ... and of their momenta
    n: int               # the number of states


def launch(part, z_s: float, tilt: float = 0.0, offset: float = 0.0, p=None,
           azimuth: float = DEFAULT_AZIMUTH) -> Launch:
    """The Launch of initial_state(part, z_s, spin, tilt, offset, p, azimuth), for every spin."""
    s = list(part.states)
    coords = coordinate_names(part)
    q = np.zeros(len(coords))
    q[coords.index("z")] = z_s
    kind = coordinates_of(part)
    if kind is None:
        if tilt != 0.0 or offset != 0.0:
            raise UserError("the reduced model keeps the top upright on the axis: use tilt = offset "
                            "= 0, or simulate the full model (--part full)")
        # as Tait-Bryan on the invariant set: omega_3 = -zeta_dot
        i_spin, along = coords.index("zeta"), -1.0
    else:
        q[coords.index("x")] = offset
        angles = tilt_angles(kind, tilt, azimuth)
        for a, v in zip(ANGLES[kind], angles):
            q[coords.index(a)] = v
        n = rotation_bs(kind, angles)[:, 2]
        want = [math.sin(tilt) * math.cos(azimuth), math.sin(tilt) * math.sin(azimuth), math.cos(tilt)]
        if not np.allclose(n, want, atol=1e-14, rtol=0):
            raise AssertionError(f"tilt convention broken: n = {n}")
        # the spin angle's rate that gives omega . n = spin, omega = vee(dR/da R^T) a_dot
        ispin = ANGLES[kind].index(SPIN_ANGLE[kind])
        W = rotation_bs_derivatives(kind, angles)[ispin] @ rotation_bs(kind, angles).T
        along = float(np.dot([W[2, 1], W[0, 2], W[1, 0]], n))    # = +1 or -1
        i_spin = coords.index(SPIN_ANGLE[kind])
    f0, Minv = legendre_map(part, q, p)
    return Launch(q, f0, Minv, i_spin, along, [s.index(c) for c in coords],
                  [s.index("p_" + c) for c in coords], len(s))


def launch_state(la: Launch, spin: float) -> np.ndarray:
    """The initial state of a Launch at `spin`: the momenta solve dq/dt = M(q)^-1 p (thesis eq.
    2.3.8) for the coordinate rates, at rest except for the spin angle's rate spin / along."""
    qdot = np.zeros(len(la.q))
    qdot[la.i_spin] = spin / la.along       # the reduced model: along = -1, exactly -spin
    x = np.zeros(la.n)
    x[la.ic] = la.q
    x[la.ip] = np.linalg.solve(la.Minv, qdot - la.f0)
    return x


def initial_state(part, z_s: float, spin: float, tilt: float = 0.0, offset: float = 0.0,
                  p=None, azimuth: float = DEFAULT_AZIMUTH) -> np.ndarray:
    """The state of the module docstring, in the part's state order."""
    return launch_state(launch(part, z_s, tilt, offset, p, azimuth), spin)


def state_scales(part, z_s: float, spin: float, pvals: dict) -> np.ndarray:
    """Magnitudes of the state components (for tolerances and errors): lengths z_s, angles 1 rad,
    linear momenta m sqrt(g z_s), angular momenta max(C |spin|, A sqrt(g / z_s))."""
    m, g, A, C = pvals["m"], pvals["g"], pvals["A"], pvals["C"]
    out = []
    for name in part.states:
        if name in ("x", "y", "z"):
            out.append(z_s)
        elif name in ("p_x", "p_y", "p_z"):
            out.append(m * math.sqrt(g * z_s))
        elif name.startswith("p_"):
            out.append(max(C * abs(spin), A * math.sqrt(g / z_s)))
        else:
            out.append(1.0)
    return np.array(out)


def default_box(part, z_s: float, half_width: float | None = None) -> Box:
    """|z - z_s| <= b and sqrt(x^2 + y^2) <= b, b = z_s / 2 unless given."""
    b = 0.5 * z_s if half_width is None else float(half_width)
    if not (b > 0 and math.isfinite(b)):
        raise UserError(f"box half-width {half_width} must be a positive length (m)")
    s = list(part.states)
    ix = s.index("x") if "x" in s else -1
    iy = s.index("y") if "y" in s else -1
    return Box(iz=s.index("z"), z_lo=z_s - b, z_hi=z_s + b, ix=ix, iy=iy,
               r_max=b if ix >= 0 else math.inf)


def fastest_period(spin: float, pvals: dict, stiffness: float) -> tuple[float, str]:
    """The fastest time scale of the motion near the hover height, and what it is: the shortest of
    the spin period 2 pi / |spin|, the nutation period 2 pi A / (C |spin|) and the vertical bounce
    2 pi sqrt(m / U''), U'' = mu Phi_3(z_s) (thesis 3.3.3). In the scene's units of time (scenes
    may be dimensionless): never a fixed number of seconds."""
    periods = []
    if stiffness > 0:
        periods.append((2 * math.pi * math.sqrt(pvals["m"] / stiffness),
                        "the vertical bounce period 2 pi sqrt(m / U'')"))
    if spin:
        periods.append((2 * math.pi / abs(spin), f"the spin period 2 pi / |spin| at spin {spin:g}"))
        periods.append((2 * math.pi * pvals["A"] / (pvals["C"] * abs(spin)),
                        f"the nutation period 2 pi A / (C |spin|) at spin {spin:g}"))
    periods = [(T, what) for T, what in periods if math.isfinite(T) and T > 0]
    if not periods:
        raise UserError("the top has no spin and no vertical stiffness at its hover height: no time "
                        "scale to integrate over")
    return min(periods)


def vertical_stiffness(model, p, z_s: float, pvals: dict) -> float:
    """U''(z_s) = mu Phi_3(z_s), the vertical stiffness at the hover height (thesis 3.3.3)."""
    return pvals["mu"] * float(model.onaxis(z_s, p)[3])


def time_scale(model, p, z_s: float, spin: float, pvals: dict) -> tuple[float, str]:
    """fastest_period at the hover height z_s of parameters p."""
    return fastest_period(spin, pvals, vertical_stiffness(model, p, z_s, pvals))


def default_t_end(model, part: str, p) -> float:
    """1 time unit, or FRICTION_T_END_TAUS spin decay times for a full model in air."""
    if part == "full" and flight.has_friction(model) and model.pvals(p)["k_spin"] > 0:
        return FRICTION_T_END_TAUS / model.pvals(p)["k_spin"]
    return 1.0


def simulate(model, spin: float, tilt: float | None = None, offset: float = 0.0,
             t_end: float | None = None,
             integrator: str = DEFAULT, tol: float | None = 1e-9, box: float | None = None,
             plot: str | Path | None = None, part: str = "full", h: float | None = None,
             n_out: int = 2000, params: dict | None = None,
             azimuth: float = DEFAULT_AZIMUTH, save: str | Path | None = None,
             trajectory: bool = False) -> dict:
    """Run one trajectory and answer docs/contract.md's `simulate` keys (plus details).

    box: the half-width of the box (m), default z_s / 2. params: parameter values overriding the
    scene's for this run (names of manifest.json `parameters`). integrator: a name of
    runtime/integrators_table.py or "auto" (resolved from tol: the answer's `integrator` is the
    method that ran, `integrator_requested` the name asked for, `integrator_choice` auto's reason).
    tilt None: DEFAULT_TILT for the full model, 0 for the reduced one; t_end None: default_t_end.
    save: write the samples to a .csv or .npz file (runtime/trajectory_file.py; `saved` names it);
    trajectory: also return them as out["trajectory"] = {column: array} (not JSON: the API's)."""
    if save is not None:
        trajectory_file.check_path(save)
    spin = real(spin, "--spin", unit="rad/s")
    tilt = None if tilt is None else real(tilt, "--tilt", max_abs=math.pi, unit="rad")
    offset = real(offset, "--offset", unit="m")
    azimuth = real(azimuth, "--tilt-azimuth", unit="rad")
    t_end = None if t_end is None else real(t_end, "--t-end (run length)", unit="s")  # its range: check_options
    n_out = count(n_out, "--n-out")
    tol = None if tol is None else real(tol, "--tol (tolerance)")
    box = None if box is None else real(box, "--box", positive=True, unit="m")
    h = None if h is None else real(h, "--step", positive=True, unit="s")
    pt = model.part(part)
    p = model.with_params(params or {})
    pvals = model.pvals(p)
    tilt_default = tilt is None
    if tilt is None:
        tilt = DEFAULT_TILT if coordinates_of(pt) is not None else 0.0
    if t_end is None:
        t_end = default_t_end(model, part, p)
    requested, integrator = integrator, resolve(integrator, tol, h)   # "auto": dop853 or vern9
    entry = lookup(integrator)
    z_s = hover_height(model, p)
    T, what = time_scale(model, p, z_s, spin, pvals)
    bx = default_box(pt, z_s, box)
    if entry.fixed_step and h is None:
        h = T / 100
    x0 = initial_state(pt, z_s, spin, tilt, offset, p, azimuth)
    if bx.excess(x0) > 0:
        raise UserError(f"the initial state is already outside the box (offset {offset} m vs half-width "
                        f"{bx.z_hi - z_s:.4g} m); pass a smaller --offset or a larger --box")
    scale = state_scales(pt, z_s, spin, pvals)
    res = integrate(pt, x0, t_end, method=integrator, tol=tol if not entry.fixed_step else None,
                    h=h, p=p, box=bx, n_out=n_out, scale=scale,
                    monitor_energy=entry.monitors_energy, time_scale=T, time_scale_what=what)
    air = part == "full" and flight.has_friction(model)
    fl = None
    if air:
        st = stability_of(model, p=p, z_s=z_s)    # the ideal top's interval at z_s (rates set to 0)
        fl = flight.flight(model, pt, p, res, x0, spin, z_s, t_end, st.spin_interval,
                           lambda X: spin_rate(pt, X, pvals["C"], p))
    out = summarize(pt, res, x0, p, z_s, bx, spin, tilt, offset, t_end, integrator, tol, h, plot, fl)
    out["tilt_azimuth"] = azimuth
    out["tilt_default"] = tilt_default and coordinates_of(pt) is not None
    if on_invariant_set(pt, tilt, offset):
        out["levitating"], out["untested"] = None, UNTESTED
    out["integrator_requested"] = requested
    if requested == AUTO:
        out["integrator_choice"] = auto_note(tol)
    if save is not None or trajectory:
        names, table = trajectory_table(pt, res, p)
        out["saved"] = str(trajectory_file.write(save, names, table)) if save is not None else None
        if trajectory:
            out["trajectory"] = {n: table[:, i] for i, n in enumerate(names)}
    return out


def trajectory_table(pt, res: Result, p) -> tuple[list[str], np.ndarray]:
    """The samples of a run as columns (runtime/trajectory_file.py): t, the states, energy, L_z,
    L_n and tilt, each derived column from a generated function in one C call."""
    X = np.atleast_2d(res.X)
    H = res.energy if res.energy is not None else _rows(pt, "energy", X, p)[:, 0]
    inv = invariants(pt, X, p)
    cols = [np.asarray(res.t, float)[:, None], X, np.asarray(H, float)[:, None], inv,
            tilt_of(pt, X)[:, None]]
    return ["t", *pt.states, "energy", "L_z", "L_n", "tilt"], np.hstack(cols)


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


def summarize(pt, res: Result, x0, p, z_s, bx: Box, spin, tilt, offset, t_end, integrator, tol, h,
              plot, fl: dict | None = None) -> dict:
    """simulate's answer. fl: the flight block of a run in air (runtime/flight.py); there the energy
    drift is the residual of the energy balance and L.n is compared with its exponential decay."""
    s = list(pt.states)
    X = res.X
    H = res.energy if res.energy is not None else _rows(pt, "energy", X, p)[:, 0]
    H0 = pt.energy(x0, p)
    names = pt.model.param_names if hasattr(pt, "model") else []
    pv = dict(zip(names, p))
    terms = abs(H0)
    if names:
        terms = max(terms, pv["m"] * abs(pv["g"]) * z_s + 0.5 * pv["C"] * spin ** 2)
    drift = np.abs(H - H0) / terms
    z = X[:, s.index("z")]
    r = np.hypot(X[:, s.index("x")], X[:, s.index("y")]) if "x" in s else np.zeros(len(X))
    exc = np.sqrt(r ** 2 + (z - z_s) ** 2)
    tilt_t = tilt_of(pt, X)
    inv = invariants(pt, np.vstack([x0, res.x_final]), p)
    lz0, lz1 = float(inv[0, 0]), float(inv[1, 0])
    pz = ([float(x0[s.index("p_zeta")]), float(res.x_final[s.index("p_zeta")])]
          if "p_zeta" in s else None)
    out = {
        "levitating": res.status == "completed",
        "t_survived": res.t_final,
        "max_excursion": float(exc.max()),
        "energy_drift": float(drift.max()),
        "rhs_evals": res.rhs_evals,
        "wall_s": res.wall_s,
        "final_state": {k: float(v) for k, v in zip(s, res.x_final)},
        "status": res.status,
        "message": res.message,
        "z_s": z_s,
        "spin": {"rad_s": spin, "hz": spin / (2 * math.pi), "rpm": spin * 60 / (2 * math.pi)},
        "tilt": tilt, "offset": offset, "t_end": t_end,
        "integrator": integrator, "backend": res.backend,
        "tol": tol if not lookup(integrator).fixed_step else None,
        "step": h if lookup(integrator).fixed_step else None,
        "box": {"z": [bx.z_lo, bx.z_hi], "r_max": bx.r_max if math.isfinite(bx.r_max) else None},
        "max_height_deviation": float(np.abs(z - z_s).max()),
        "max_radial_offset": float(r.max()),
        "max_tilt": float(tilt_t.max()),
        "energy_drift_final": float((H[-1] - H0) / terms) if len(H) else None,
        "energy_scale": terms,
        "conserved": {
            "energy": [float(H0), float(pt.energy(res.x_final, p))],
            "L_z": [lz0, lz1],
            "p_zeta": pz,
        },
        "conserved_max_deviation": _deviations(pt, X, x0, p, pv, spin, float(drift.max())),
        "part": pt.name if hasattr(pt, "name") else None,
        "coordinates": coordinates_of(pt),
        "plot": None,
    }
    if fl is not None:
        out["flight"] = fl
        out["fall_spin"], out["t_cross"] = fl["fall_spin"], fl["t_cross"]
        out["energy_drift"] = fl["energy_balance"]
        out["energy_drift_final"] = None
        out["conserved_max_deviation"] = {"energy_balance": fl["energy_balance"], "L_z": None,
                                          "L_n_decay": fl["spin_decay_deviation"]}
    if plot:
        scene = getattr(getattr(pt, "model", None), "scene", None)
        u = Units.of_scene(scene) if scene is not None else Units.of(pv.get("g"))
        name = getattr(scene, "name", "")
        if fl is not None:
            out["plot"] = str(draw_flight(res.t, z - z_s, spin_rate(pt, X, pv["C"], p), plot, out, u, name))
        else:
            out["plot"] = str(draw(res.t, z - z_s, r, tilt_t, plot, out, u, name))
    return out


def _rows(pt, kind: str, X, p) -> np.ndarray:
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
    return np.array([[angular_momentum_z(pt, x), spin_momentum(pt, x)] for x in X])


def _deviations(pt, X, x0, p, pv: dict, spin: float, energy: float) -> dict:
    """The largest relative deviation over the samples of H (given), L_z and L.n, each relative to
    max(|its start value|, C |spin|) (the spin's angular momentum: the scale of both)."""
    c_spin = pv.get("C", 0.0) * abs(spin)
    inv = invariants(pt, np.vstack([x0, X]), p)
    lz, ln = inv[:, 0], inv[:, 1]
    return {"energy": energy,
            "L_z": largest_deviation(lz, max(abs(lz[0]), c_spin)),
            "L_n": largest_deviation(ln, max(abs(ln[0]), c_spin))}


def draw(t, dz, r, tilt, path, info, u: Units, scene: str = "") -> Path:
    """Height above z_s, radial offset and tilt against time (matplotlib, Agg; runtime/plotting.py
    style): mm and s in an SI scene, the scene's own units otherwise (u: runtime/human.py)."""
    plt = pyplot()
    style()
    k, lu, tu = (1e3, "mm", "s") if u.si else (1.0, "scene units", "time units")
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
    ax[0].plot(t, dz * k, label="z - z_s")
    ax[0].axhline(0, color="0.5", lw=0.8, ls="--", label=f"z_s = {u.length(info['z_s'])}")
    ax[0].set_ylabel(f"height above z_s ({lu})")
    ax[1].plot(t, r * k, color="C1", label="sqrt(x^2 + y^2)")
    ax[1].set_ylabel(f"radial offset ({lu})")
    ax[2].plot(t, np.degrees(tilt), color="C2", label="angle of the axis to the vertical")
    ax[2].set_ylabel("tilt (deg)")
    ax[2].set_xlabel(f"t ({tu})")
    for a in ax:
        a.legend(loc="best")
    verdict = "levitating" if info["levitating"] else info["status"]
    ax[0].set_title(f"{scene}: spin {u.rate(info['spin']['rad_s'], 4)}, z_s = {u.length(info['z_s'])}\n"
                    f"{verdict} for {u.time(info['t_survived'])}", fontsize="medium")
    fig.tight_layout()
    return save_figure(fig, path)


def draw_flight(t, dz, w, path, info, u: Units, scene: str = "") -> Path:
    """A flight in air: the spin and the height above z_s against time, with the linear spin limits
    at z_s and the adiabatic crossing time drawn in (runtime/flight.py; u: runtime/human.py)."""
    plt = pyplot()
    style()
    fl = info["flight"]
    k, lu, tu, ru = (1e3, "mm", "s", "rad/s") if u.si else (1.0, "scene units", "time units", "rad/time")
    fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    ax[0].plot(t, w, label="spin omega_3")
    iv = fl["spin_interval"]
    if iv:
        ax[0].axhline(iv[0], color="C3", ls="--", lw=1, label=f"lower limit {sig(iv[0], 4)} {ru}")
        if iv[1] < 1.2 * max(w):
            ax[0].axhline(iv[1], color="C4", ls="--", lw=1, label=f"upper limit {sig(iv[1], 4)} {ru}")
    if fl["t_cross"] is not None:
        for a in ax:
            a.axvline(fl["t_cross"], color="0.5", ls=":", lw=1)
        ax[0].plot([], [], color="0.5", ls=":", label=f"adiabatic crossing t = {sig(fl['t_cross'], 4)} {tu}")
    ax[0].set_ylabel(f"spin ({ru})")
    ax[1].plot(t, dz * k, color="C1", label="z - z_s")
    ax[1].set_ylabel(f"height above z_s ({lu})")
    ax[1].set_xlabel(f"t ({tu})")
    for a in ax:
        a.legend(loc="best", fontsize="small")
    verdict = (f"falls after {sig(fl['flight_time'], 4)} {tu} at spin {sig(fl['fall_spin'], 4)} {ru}"
               if fl["fell"] else f"still up after {sig(info['t_survived'], 4)} {tu}")
    ax[0].set_title(f"{scene} in air: launched at {sig(info['spin']['rad_s'], 4)} {ru}; {verdict}",
                    fontsize="medium")
    fig.tight_layout()
    return save_figure(fig, path)
