"""The linear modes of a top whose magnet is tilted off its axis, over a level axisymmetric base: in
the frame turning about the vertical with the spin (runtime/physics/apparatus/rotating_equilibrium.py).

There the steady motion is a relative equilibrium, a fixed point of the augmented Hamiltonian
G = H + sigma L_z, and its ten nontrivial eigenvalues (of Jsym Hess G on the plane of the conserved
L_z less the rotation's direction: RotatingTop.check) are five pairs +-i omega: the modes in the
turning frame. Each is reported with

* `frequency`: omega = |Im lambda| in the turning frame (rad/s), and its energy (Krein) sign, that
  of G's quadratic part on the mode (G, not H: the frame's energy; two modes can collide only if
  their signs differ, as for the level top, runtime/physics/stability/modes.py);
* its name, followed from the aligned top (moment tilt 0, where the turning frame's frequency of a
  transverse mode is |omega_s - sigma|, omega_s its lab frequency signed by its sense,
  runtime/physics/stability/modes.py's names; the bounce keeps its own) through STEPS steps in the moment
  tilt, each mode matched to the nearest frequency of the step before;
* its lab-frame frequency where it is meaningful: a perturbation x + i y = c_+ e^{i omega t} +
  c_- e^{-i omega t} in the turning frame is seen in the lab at omega + Omega and -omega + Omega
  (Omega the frame's rate, signed like the spin), the vertical part at omega. At moment tilt 0
  each mode is one of the three and its lab frequency is the level top's exactly; with the moment
  tilted the modes mix them (by O(b)). The lab frequency is given where one part carries at least
  PURE of the mode's weight (m|u|^2 + A|v|^2 per sense of rotation, m|z|^2 the vertical part, u the
  horizontal position, v the axis' tilt, as modes.py weighs them), with its sense relative to the
  spin; else None ("mixed").

Over a tilted base with the magnet aligned the top's steady motion is an equilibrium off the axis,
whose modes runtime/physics/stability/tilted_modes.py gives (turning_modes hands it on). With the magnet tilted
over a tilted base, a plate without axial symmetry or a magnet off the centre no rotation about the
vertical is a symmetry: the tilted magnet's steady motion is a periodic orbit (runtime/physics/
apparatus/multipliers.py, by shooting) and its modes are not given; `refusal` says so in one line. No sympy here.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.validate import spin_rate
from levitron.runtime.words import si

STEPS = 8         # continuation steps in the moment tilt that carry the names from the aligned top
PURE = 0.9        # the share of one lab frequency in a mode above which its lab frequency is given
_SI = Units(si=True)


def off_axis(model, p: np.ndarray) -> bool:
    """Whether the steady motion at parameters p is off the axis (runtime/physics/stability/modes.py OFF_AXIS)."""
    from levitron.runtime.physics.stability.modes import OFF_AXIS
    P = model.pvals(p)
    return any(P.get(k, 0.0) != 0 for k in OFF_AXIS)


def refusal(model, p: np.ndarray) -> str | None:
    """The one line saying that the modes at parameters p are not given, or None where the top is
    level and aligned (runtime/physics/stability/modes.py's) or the turning frame carries them (this module)."""
    from levitron.runtime.physics.apparatus import rotating_equilibrium as req
    P = model.pvals(p)
    if not off_axis(model, p):
        return None
    why = req.refusal(model, p)
    if why is None and P.get("moment_offset", 0.0) != 0:
        why = f"the magnet is {si(P['moment_offset'], 'm')} off the centre"
    if why is None:
        return None
    if P.get("moment_tilt", 0.0) == 0 and P.get("moment_offset", 0.0) == 0:
        return None             # a tilted base, the magnet aligned: the equilibrium's (tilted_modes.py)
    return (f"no linear modes: {why}, so the tilted magnet's steady motion is a periodic orbit, a fixed point "
            "in no frame turning about the vertical; its modes need the Floquet route (by shooting) and are "
            "not given")


@dataclass(frozen=True)
class TurningMode:
    """One mode in the turning frame: `frequency` (rad/s) and `sense` there (+1 with the spin, -1
    against, 0 the bounce), `krein` the sign of G's energy on it (0 off the imaginary axis),
    `eigenvalue` (1/s), `lab_frequency` and `lab_sense` (None where mixed), `purity` the share of
    the part that the lab frequency belongs to."""

    name: str
    frequency: float
    sense: int
    krein: int
    eigenvalue: complex
    lab_frequency: float | None
    lab_sense: int | None
    purity: float

    def as_json(self) -> dict:
        lam = self.eigenvalue
        return {"name": self.name, "frequency": self.frequency, "sense": self.sense, "krein": self.krein,
                "eigenvalue": [lam.real, lam.imag], "growth_rate": abs(lam.real) if self.krein == 0 else 0.0,
                "lab_frequency": self.lab_frequency, "lab_sense": self.lab_sense, "purity": self.purity}


@dataclass(frozen=True, repr=False)
class TurningModes:
    """The five modes at `spin` (rad/s) of the top with its moment tilted by `moment_tilt` (rad),
    in the frame turning about the vertical at the spin; `stable`: all on the imaginary axis."""

    spin: float
    moment_tilt: float
    modes: tuple[TurningMode, ...]
    stable: bool
    residual: float
    units: Units = field(default=_SI, compare=False)

    def __getitem__(self, name: str) -> TurningMode:
        for m in self.modes:
            if m.name == name:
                return m
        raise KeyError(f"{name!r}: the modes are {[m.name for m in self.modes]}")

    def as_json(self) -> dict:
        return {"spin": self.spin, "stable": self.stable, "frame": "turning",
                "frame_rate": self.spin, "moment_tilt": self.moment_tilt,
                "modes": [m.as_json() for m in self.modes], "orbit_residual": self.residual,
                "source": "eigenvalues of Jsym Hess(H + sigma L_z) at the relative equilibrium in the frame "
                          "turning about the vertical (runtime/physics/stability/rotating_modes.py)"}


def _picked(w: np.ndarray, tol: np.ndarray) -> list[int]:
    """One eigenvalue of each pair: Im > 0, or on the real axis the growing one (as modes.py)."""
    return [k for k in range(len(w)) if w[k].imag > tol[k] or (abs(w[k].imag) <= tol[k] and w[k].real > 0)]


def _spectrum(rt, sigma: float) -> tuple[list[dict], float]:
    """The modes of RotatingTop rt at sigma (one dict each: lambda, frequency, Krein sign of G, the
    weights of the three lab parts) and the orbit's residual."""
    from levitron.runtime.physics.routes.eigen_route import balancing
    c = rt.check(sigma)
    hess, gl, _ = rt.fn.A(c.state, sigma, rt.p)
    s = rt.scales(sigma)
    A = (rt.fn.Jsym @ hess) * s[None, :] / s[:, None]
    g = gl.ravel() * s
    xi = (rt.fn.Jsym @ gl.ravel()) / s
    U = np.linalg.qr(g[:, None], mode="complete")[0][:, 1:]
    Q = U @ np.linalg.qr((U.T @ xi)[:, None], mode="complete")[0][:, 1:]
    M = Q.T @ A @ Q
    d = balancing(M)
    w, X = np.linalg.eig(M * np.outer(1.0 / d, d))
    X = X * d[:, None]
    st = rt.states
    ix, iy, iz, ith, iph = (st.index(k) for k in ("x", "y", "z", "vartheta", "phi"))
    m, A_ = rt.P["m"], rt.P["A"]
    out = []
    for k in _picked(w, c.tolerance):
        v = s * (Q @ X[:, k])                      # the mode in the full states
        on_axis = abs(w[k].real) <= c.tolerance[k]
        energy = float((v.conj() @ hess @ v).real)
        ccw = m * abs(v[ix] + 1j * v[iy]) ** 2 + A_ * abs(v[ith] + 1j * v[iph]) ** 2
        cw = m * abs(v[ix] - 1j * v[iy]) ** 2 + A_ * abs(v[ith] - 1j * v[iph]) ** 2
        out.append({"lam": complex(w[k]), "freq": abs(float(w[k].imag)), "krein": (1 if energy > 0 else -1)
                    if on_axis else 0, "parts": np.array([ccw / 2, cw / 2, m * abs(v[iz]) ** 2])})
    return out, c.residual


def _matched(prev: np.ndarray, now: np.ndarray) -> np.ndarray:
    """The index into `now` of each of `prev`'s frequencies (the assignment of least total change)."""
    from scipy.optimize import linear_sum_assignment
    _, cols = linear_sum_assignment(np.abs(prev[:, None] - now[None, :]))
    return cols


def modes_at(model, spin, height=None):
    """What `Study.modes` answers: runtime/physics/stability/modes.py's Modes.at for the level, aligned top;
    with the magnet tilted over a level axisymmetric base the TurningModes; elsewhere off the axis
    a UserError saying in one line why none are given."""
    from levitron.runtime.physics.stability.modes import Modes
    if not off_axis(model, model.p):
        return Modes.at(model, spin, height)
    if height is not None:
        raise UserError("«height» analyses a top on the axis of a level base: leave it out")
    return turning_modes(model, spin_rate(spin))


def turning_modes(model, spin: float, p: np.ndarray | None = None):
    """The modes (module docstring) of the model's top at parameters p (the scene's by default):
    its moment tilted over a level axisymmetric base, TurningModes; its base tilted, the magnet
    aligned, runtime/physics/stability/tilted_modes.py's Modes; a UserError with `refusal`'s line elsewhere."""
    from levitron.runtime.physics.apparatus import rotating_equilibrium as req
    from levitron.runtime.physics.stability.modes import BOUNCE, Modes
    from levitron.runtime.physics.apparatus.periodic_orbit import NoOrbit
    from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium
    from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
    p = without_friction(model, model.p if p is None else p)
    why = refusal(model, p)
    if why is not None:
        raise UserError(why)
    sigma = spin_rate(spin)
    P = model.pvals(p)
    if P.get("moment_tilt", 0.0) == 0 and P.get("base_tilt", 0.0) != 0:    # an equilibrium off the axis
        from levitron.runtime.physics.stability.tilted_modes import tilted_base_modes
        return tilted_base_modes(model, sigma, p)
    b = model.pvals(p)["moment_tilt"]
    aligned = model.with_params({"moment_tilt": 0.0}, p)
    res0 = tilted_analysis(model, aligned)
    if not res0.z_s:
        raise UserError(f"no linear modes: the aligned top has no stable hover height ({res0.reason})")
    z_level = res0.equilibrium["z_level"]
    level = Modes.of(model, sigma, z_level, res0.spin_interval, aligned, hessian="jacobian")
    rt = req.RotatingTop(model, aligned, z_level)
    lz = float(model.fast("full_invariants", aligned)(rt.solve(sigma))[0])
    turn = 1.0 if lz > 0 else -1.0         # the spin's sense about the vertical in the x-y plane
    names = [md.name for md in level.modes]
    # the turning frame's frequency of each level mode, signed by its sense there
    freq = np.array([md.frequency if md.name == BOUNCE else abs(md.signed - sigma) for md in level.modes])
    sense_turning = [0 if md.name == BOUNCE else (1 if md.signed > sigma else -1) for md in level.modes]
    try:
        for t in np.linspace(0.0, b, STEPS + 1):
            rows, residual = _spectrum(rt.at_tilt(float(t)), sigma)
            cols = _matched(freq, np.array([r["freq"] for r in rows]))
            rows = [rows[j] for j in cols]
            freq = np.array([r["freq"] for r in rows])
    except (NoOrbit, NoEquilibrium) as exc:
        raise UserError(f"no linear modes at {si(sigma, 'rad/s')}: the tilted magnet's steady motion does not "
                        f"exist there on the branch from the aligned top ({exc})") from None
    modes = []
    for name, sense, r in zip(names, sense_turning, rows):
        share = r["parts"] / r["parts"].sum()
        k = int(np.argmax(share))
        if share[k] < PURE:
            lab, lab_sense = None, None
        elif k == 2:
            lab, lab_sense = r["freq"], 0
        else:              # the circular part's lab rate, in the x-y plane's sense, then the spin's
            signed = turn * ((r["freq"] if k == 0 else -r["freq"]) + turn * sigma)
            lab, lab_sense = abs(signed), (1 if signed > 0 else -1)
        modes.append(TurningMode(name, r["freq"], sense, r["krein"], r["lam"], lab, lab_sense, float(share[k])))
    return TurningModes(sigma, float(b), tuple(modes), all(m.krein != 0 for m in modes), residual,
                        Units.of_scene(model.scene))


def lines(d: dict, u: Units) -> list[str]:
    """The plain view of TurningModes.as_json()."""
    sense = {1: "with the spin", -1: "against the spin", 0: "vertical"}
    out = [f"modes at {u.rate(d['spin'])} in the frame turning with the spin (the magnet tilted by "
           f"{u.angle(d['moment_tilt'])})" + ("" if d["stable"] else ", not all stable") + ":"]
    for m in d["modes"]:
        energy = {1: "energy +", -1: "energy - (Krein)"}.get(m["krein"]) or \
            f"unstable (grows at {u.value(m['growth_rate'], '1/s', 3)})"
        lab = ("lab: mixed" if m["lab_frequency"] is None else
               f"lab: {u.rate(m['lab_frequency']).split(' (')[0]}, {sense[m['lab_sense']]}")
        out.append(f"  {m['name']}: {u.rate(m['frequency']).split(' (')[0]}, {sense[m['sense']]}, {energy}; {lab}")
    return out

