"""The launch: the initial state at the hover height (thesis 3.3.2-3.3.3) with the axis tilted and
the top spinning, its momenta through the model's own Legendre map (thesis eq. 2.3.8), the box the
top must stay in, the state scales and the fastest time scale (runtime/simulate/run.py's module
docstring has the conventions). A launch with tilt 0 and offset 0 lies on the invariant set
(thesis 3.2.1) and tests nothing: DEFAULT_TILT is the default perturbation."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.words import si, si_unit
from levitron.runtime.integrate.run import Box
from levitron.runtime.physics.routes.eigen_route import growth_rate, transverse_matrix
from levitron.runtime.simulate.invariants import rows_of
from levitron.runtime.simulate.rotations import (ANGLES, DEFAULT_AZIMUTH, SPIN_ANGLE, body_rate_matrix,
                                        coordinates_of, rotation_bs, rotation_bs_derivatives, tilt_angles)


def coordinate_names(part) -> list[str]:
    return [s for s in part.states if not s.startswith("p_")]


def legendre_map(part, q: np.ndarray, p=None) -> tuple[np.ndarray, np.ndarray]:
    """The coordinate rows of the generated rhs at coordinates q, dq/dt = M(q)^-1 p_q (thesis eq.
    2.3.8), linear in the momenta: (f0, Minv), f0 the rows at p_q = 0 and Minv's column k the rows
    at p_k = 1 less f0. The launch does not use it (momentum_column builds M forward): it is the
    second route that checks the launch's momenta against the generated equations."""
    s = list(part.states)
    coords = coordinate_names(part)
    ic = [s.index(c) for c in coords]
    ip = [s.index("p_" + c) for c in coords]
    E = np.zeros((1 + len(ip), len(s)))        # row 0 at p_q = 0, row 1 + k at p_k = 1
    E[:, ic] = q
    E[1 + np.arange(len(ip)), ip] = 1.0
    rows = rows_of(part, "rhs", E, p)[:, ic]   # one C call
    return rows[0], (rows[1:] - rows[0]).T


def momentum_column(part, q: np.ndarray, i_rate: int, pvals: dict) -> np.ndarray:
    """dp/d(qdot_i): column i of the mass matrix M(q) of p = M(q) qdot = dL/d(qdot) (thesis eq.
    2.3.8), from T = m v^2 / 2 + omega^T diag(A, A, C) omega / 2 (thesis eqs. 2.1.11-2.1.14):
    the translations' block is m 1, the angles' J^T diag(A, A, C) J. Computed forward, never by
    inverting the generated map dq/dt = M^-1 p: in z-x-z angles M^-1 holds 1/(A sin^2 theta)
    beside 1/C, and near the upright top (theta ~ 1e-8) the 1/C is lost to rounding."""
    coords = coordinate_names(part)
    kind = coordinates_of(part)
    col = np.zeros(len(coords))
    name = coords[i_rate]
    if name in ("x", "y", "z"):
        col[i_rate] = pvals["m"]
        return col
    if kind is None:    # the reduced model: z and the spin angle zeta about the vertical
        col[i_rate] = pvals["C"]
        return col
    names = ANGLES[kind]
    J = body_rate_matrix(kind, [q[coords.index(a)] for a in names])
    inertia = np.array([pvals["A"], pvals["A"], pvals["C"]])
    block = J.T @ (inertia * J[:, names.index(name)])
    for k, a in enumerate(names):
        col[coords.index(a)] = block[k]
    return col


DEFAULT_TILT = 0.005             # rad: the default launch's tilt (module docstring)


def on_invariant_set(part, tilt: float, offset: float) -> bool:
    """A run on I (thesis 3.2.1), where the ideal top stays at any spin, so that it tests nothing:
    a full-model launch with tilt 0 and offset 0, or any run of the reduced model (the motion on I
    itself, thesis 3.2.12: the bounce and the spin, no tilt)."""
    return coordinates_of(part) is None or (tilt == 0.0 and offset == 0.0)


UNTESTED = ("the launch lies on the invariant set (tilt 0, offset 0; thesis 3.2.1), where the ideal "
            "top stays at any spin: this run tests no stability; give a tilt (e.g. «tilt» "
            f"{DEFAULT_TILT}) or an offset")
UNTESTED_REDUCED = ("the reduced model is the motion on the invariant set (thesis 3.2.1, 3.2.12): the "
                    "bounce and the spin, never a tilt, so the ideal top stays at any spin and this run "
                    "tests no stability; run the full model («part=full») with a tilt")


def untested_reason(part) -> str:
    """Why a run on the invariant set (on_invariant_set) tests nothing, for this part."""
    return UNTESTED if coordinates_of(part) is not None else UNTESTED_REDUCED


@dataclass(frozen=True)
class Launch:
    """The spin-free part of the initial state (module docstring): the coordinates q, the
    momenta per unit rate of the spin angle (momentum_column) and that rate per unit spin,
    1 / along. A map (runtime/scan/runners.py) computes it once per launch position and tilt for
    all its spins."""
    q: np.ndarray
    p_spin: np.ndarray   # p = M(q) qdot for a unit rate of the spin angle (momentum_column)
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
                            "= 0, or simulate the full model («part=full»)")
        # as Tait-Bryan on the invariant set: omega_3 = -zeta_dot
        i_spin, along = coords.index("zeta"), -1.0
    else:
        q[coords.index("x")] = offset
        angles = tilt_angles(kind, tilt, azimuth)
        for a, v in zip(ANGLES[kind], angles):
            q[coords.index(a)] = v
        n = rotation_bs(kind, angles)[:, 2]
        want = [math.sin(tilt) * math.cos(azimuth), math.sin(tilt) * math.sin(azimuth), math.cos(tilt)]
        if not max(abs(a - b) for a, b in zip(n, want)) <= 1e-14:
            raise AssertionError(f"tilt convention broken: n = {n}")
        # the spin angle's rate that gives omega . n = spin, omega = vee(dR/da R^T) a_dot
        ispin = ANGLES[kind].index(SPIN_ANGLE[kind])
        W = rotation_bs_derivatives(kind, angles)[ispin] @ rotation_bs(kind, angles).T
        along = float(np.dot([W[2, 1], W[0, 2], W[1, 0]], n))    # = +1 or -1
        i_spin = coords.index(SPIN_ANGLE[kind])
    p_spin = momentum_column(part, q, i_spin, part.model.pvals(p))
    return Launch(q, p_spin, i_spin, along, [s.index(c) for c in coords],
                  [s.index("p_" + c) for c in coords], len(s))


def launch_state(la: Launch, spin: float) -> np.ndarray:
    """The initial state of a Launch at `spin`: the momenta p = M(q) qdot (thesis eq. 2.3.8) of
    the top at rest except for the spin angle's rate spin / along (the reduced model: along = -1,
    exactly -spin)."""
    x = np.zeros(la.n)
    x[la.ic] = la.q
    x[la.ip] = la.p_spin * (spin / la.along)
    return x


def launch_states(la: Launch, spins: np.ndarray) -> np.ndarray:
    """launch_state at each of `spins`, (k, n): the same products, elementwise, so the same states
    bit for bit."""
    spins = np.asarray(spins, dtype=float).reshape(-1)
    X = np.zeros((spins.size, la.n))
    X[:, la.ic] = la.q
    X[:, la.ip] = la.p_spin[None, :] * (spins / la.along)[:, None]
    return X


def initial_state(part, z_s: float, spin: float, tilt: float = 0.0, offset: float = 0.0,
                  p=None, azimuth: float = DEFAULT_AZIMUTH) -> np.ndarray:
    """The state of the module docstring, in the part's state order."""
    return launch_state(launch(part, z_s, tilt, offset, p, azimuth), spin)


def tilted_start(model, part, z_s: float, spin: float, x0: np.ndarray, p) -> tuple[np.ndarray, str | None]:
    """Over a tilted base (plate.tilt): the launch's perturbation, x0 less the unperturbed launch
    on the axis, applied at the relative equilibrium off the axis with its axis along the field
    (runtime/physics/apparatus/tilted_equilibrium.py) at the launch's own spin momentum p_zeta. Returns (the
    state, what it did), or (x0, why) where the tilt leaves the top no equilibrium: it starts on the
    axis."""
    from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium, TiltedTop
    if "p_zeta" not in part.states:
        raise UserError("a run over a tilted base starts at its equilibrium in Tait-Bryan angles: "
                        "set model.coordinates = \"tait-bryan\"")
    level = initial_state(part, z_s, spin, 0.0, 0.0, p)
    C = model.pvals(p)["C"]
    sigma = level[part.states.index("p_zeta")] / C
    top = TiltedTop(model, p, z_s)
    try:
        eq = top.hamilton(model.pvals(p)["base_tilt"], sigma if sigma != 0 else 1.0)
    except NoEquilibrium as exc:
        return x0, f"{exc}: the run starts on the axis"
    off = math.hypot(*eq.position[:2])
    return eq.at_spin(sigma) + (x0 - level), (
        f"base tilted: the launch is taken at the top's equilibrium there, {si(off, 'm')} off the axis "
        "(`«levitron=stability»`); L_z is not conserved over a tilted base")


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


def outside_box(offset: float, half_width: float, which: str = "",
                fix: str = "pass a smaller «offset» or a larger «box»") -> UserError:
    """The refusal of a launch whose initial state is already outside its box (`which`: "launch
    3: " in a batch, whose commands have no box to name)."""
    return UserError(f"{which}the initial state is already outside the box (offset {si(offset, 'm', '')} "
                     f"vs half-width {si(half_width, 'm', '.4g')}); {fix}",
                     param="offset", value=offset, unit="m", hint=fix)


def default_box(part, z_s: float, half_width: float | None = None) -> Box:
    """|z - z_s| <= b and sqrt(x^2 + y^2) <= b, b = z_s / 2 unless given."""
    b = 0.5 * z_s if half_width is None else float(half_width)
    if not (b > 0 and math.isfinite(b)):
        raise UserError(f"box half-width {half_width} must be a positive length in {si_unit('m')}")
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


PERIODS = 3      # the default run length in slow periods (simulate, scan, launch)


def slow_period(model, mass: float, z_s: float, spin: float | None, p=None) -> float:
    """The longest period of the motion near the relative equilibrium at this spin: the slowest
    transverse mode of the 8-D linearisation after thesis 3.3.5, or the vertical bounce
    2 pi sqrt(m / (mu Phi_3(z_s))) (thesis 3.3.3), whichever is slower (spin None: the bounce only).
    p: the parameter vector (default the scene's). In the scene's units of time."""
    P = model.pvals(p)
    ph = np.asarray(model.onaxis(z_s, p), float)
    periods = []
    k = P["mu"] * ph[3]
    if k > 0:
        periods.append(2 * math.pi * math.sqrt(mass / k))
    if spin is not None:
        J = transverse_matrix(ph[1], ph[2], ph[3], mass, P["A"], P["C"], P["mu"], spin)
        lam = np.linalg.eigvals(J)
        im = np.abs(lam.imag)
        im = im[im > 1e-9 * max(1.0, float(np.abs(lam).max()))]
        if im.size:
            periods.append(2 * math.pi / float(im.min()))
    if not periods:
        raise UserError("no oscillation at the hover height to set a run length from; pass «t_end» T")
    return max(periods)


def linear_context(model, p, z_s: float, spin: float) -> dict:
    """What linear theory says of a run at this spin (thesis 3.3.9-3.3.16): the stable spin
    interval at z_s (exact route, None if no spin holds the top there), whether the spin lies
    inside it, and else the e-folding time of the fastest transverse mode of the 8-D linearisation
    after thesis 3.3.5 (1 / the largest real part of its eigenvalues): how long a tilt takes to
    grow by e. Near a critical spin that time is long, and a run shorter than it cannot show the
    fall."""
    from levitron.runtime.physics.stability.analysis import onaxis_refusal, stability_of
    why = onaxis_refusal(model, p)
    if why is not None:              # a two-fold plate: linear theory on the axis says nothing here
        return {"spin_interval": None, "inside": None, "e_folding_time": None, "refused": why}
    iv = stability_of(model, p=p, z_s=z_s, eigen=False).spin_interval
    inside = iv is not None and iv[0] <= spin <= iv[1]
    e_folding = None
    if not inside:
        P = model.pvals(p)
        ph = np.asarray(model.onaxis(z_s, p), float)
        rate = growth_rate(transverse_matrix(ph[1], ph[2], ph[3], P["m"], P["A"], P["C"], P["mu"], spin))
        e_folding = 1.0 / rate if rate > 0 else None
    return {"spin_interval": None if iv is None else list(iv), "inside": inside,
            "e_folding_time": e_folding}


def vertical_stiffness(model, p, z_s: float, pvals: dict) -> float:
    """U''(z_s) = mu Phi_3(z_s), the vertical stiffness at the hover height (thesis 3.3.3)."""
    return pvals["mu"] * float(model.onaxis(z_s, p)[3])


def time_scale(model, p, z_s: float, spin: float, pvals: dict) -> tuple[float, str]:
    """fastest_period at the hover height z_s of parameters p."""
    return fastest_period(spin, pvals, vertical_stiffness(model, p, z_s, pvals))
