"""Stability maps: which (spin, tilt | mass | height) starts keep the top up (DESIGN.md `scan`).

The thesis's fig. 3.8 (after Gans, Jones & Nelson / Gans et al.) shows the stable trajectories as a
function of spin and tilt. Here every grid point is one nonlinear run of the full model
(`point_run`: runtime.simulate.simulate from the same pieces, thesis 3.1-3.2: the C integrators
over the generated Hamilton equations 2.3.10-2.3.16), started at the vertically stable hover height
z_s (thesis 3.3.2-3.3.3, found once per mass rather than once per point), and a point
"levitates" when the top stays inside the box of runtime.simulate (|z - z_s| and the radial offset
at most z_s / 2) for the whole run. (A top started exactly upright on the axis, tilt 0, stays on
the invariant set of thesis 3.2.1 by symmetry and "levitates" at any spin: the tilt-0 row of a tilt
map is that symmetric solution, not a stability statement.) The second axis is one of

* ``tilt``:   the initial tilt of the symmetry axis (rad), as in `levitron simulate --tilt`;
* ``mass``:   the top's mass (kg). m is a runtime parameter of the generated model (no new
  derivation); each mass starts at its own hover height z_s(m) (the lowest vertically stable root of
  m g + mu Phi_2(z) = 0, thesis 3.3.2). Masses the plate cannot hold stably are marked not levitating
  without a run (status "no_hover_height");
* ``height``: the initial vertical displacement as a FRACTION of z_s: the top starts at rest (apart
  from its spin) at z_0 = z_s (1 + height). A fraction, not a length, because scenes may be
  dimensionless (DESIGN.md); |height| < 1/2 keeps the start inside the box.

For the mass and height axes the runs start with the small tilt ``base_tilt`` (default 0.01 rad):
an upright top on the axis stays there by symmetry, whatever its linear stability, so a seed is
needed for an unstable transverse mode to grow.

Default run length: ``PERIODS`` (3) periods of the slowest motion at the relative equilibrium, i.e.
the slowest transverse (precession/wobble) mode of the 8-D linearisation after thesis 3.3.5
(runtime.linear.transverse_matrix) at a spin inside the linear interval, or the vertical bounce
2 pi sqrt(m / (mu Phi_3)) (thesis 3.3.3) if that is slower. For the thesis plate with a 51.5 g top
the slow mode is ~1.8 rad/s (3.5 s), so the default is ~10.5 s; a top that is linearly unstable
typically leaves the box within a few e-folding times, and over three slow periods even weak
instabilities near the ends of the interval (growth ~0.5/s from a 0.01 rad seed) show. A mass
scan takes the median slow period over the masses that some spin stabilises (near the critical
height z_c the vertical bounce period diverges, so the longest would be unbounded).

The linear stability interval (thesis 3.3, runtime.linear.analyse: exact discriminant route) is
reported beside the map, per value of the second axis (it changes only with the mass), together
with the fraction of grid points where the nonlinear run agrees with it.

Parallelism: serial, local processes (concurrent.futures.ProcessPoolExecutor, spawn; each worker
loads the model once in its initializer, and the compiled C library is found in the content-hash
cache of runtime/cbuild.py, so no worker recompiles), or a dask.distributed cluster (optional
dependency, the `cluster` extra; the workers need this package and the scene file at the same
path). Runs are deterministic, so all three give the same map.
"""
from __future__ import annotations

import math
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from runtime.errors import UserError

AXES = ("tilt", "mass", "height")
UNITS = {"spin": "rad/s", "tilt": "rad", "mass": "kg", "height": "fraction of z_s"}
PERIODS = 3            # default run length in slow periods (see the module docstring)
BASE_TILT = 0.01       # rad, the seed tilt of mass and height scans
N_OUT = 100            # dense-output samples per run: only the survival matters here
MAX_POINTS = 1_000_000


# ----------------------------------------------------------------------------- options

def parse_range(text: str, label: str) -> np.ndarray:
    """'LO:HI:N' -> N evenly spaced values from LO to HI (both included); N = 1 needs LO = HI."""
    parts = str(text).split(":")
    if len(parts) != 3:
        raise UserError(f"--{label} {text!r} must be LO:HI:N (e.g. --{label} 0:1:10)")
    try:
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise UserError(f"--{label} {text!r}: LO and HI must be numbers, e.g. --{label} 0:1:10") from None
    try:
        n = int(parts[2])
    except ValueError:
        raise UserError(f"--{label} {text!r}: N must be a whole number of grid points, e.g. "
                        f"--{label} {parts[0]}:{parts[1]}:10") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise UserError(f"--{label} {text!r}: LO and HI must be finite numbers")
    if n < 1:
        raise UserError(f"--{label} {text!r}: N = {n} must be at least 1 (the number of grid points)")
    if lo > hi:
        raise UserError(f"--{label} {text!r}: LO = {lo:g} is above HI = {hi:g}; swap them "
                        f"(--{label} {hi:g}:{lo:g}:{n})")
    if n == 1 and lo != hi:
        raise UserError(f"--{label} {text!r}: one grid point needs LO = HI (e.g. --{label} {lo:g}:{lo:g}:1),"
                        " or pass N >= 2")
    return np.linspace(lo, hi, n)


def check_axis(axis: str, values: np.ndarray) -> None:
    """The physical range of the second axis (mass > 0, |height| < 1/2)."""
    if axis == "mass" and values[0] <= 0:
        raise UserError(f"--mass must be positive (kg); got LO = {values[0]:g}")
    if axis == "height" and not (values[0] > -0.5 and values[-1] < 0.5):
        raise UserError(f"--height is the displacement as a fraction of z_s and must lie strictly "
                        f"between -0.5 and 0.5 (the box is z_s / 2 wide); got {values[0]:g}:{values[-1]:g}")


# ----------------------------------------------------------------------------- one grid point

@dataclass(frozen=True)
class Common:
    """What every grid point shares (picklable: sent to the workers)."""
    scene: str                  # a scene name or an absolute path
    overrides: tuple[str, ...]  # the --set strings
    axis: str
    t_end: float
    integrator: str
    tol: float | None
    base_tilt: float
    hover: tuple = ()           # z_s per value of the other axis (None: that mass does not hover)
    h: float | None = None      # fixed-step integrators: None = runtime.simulate's default step


_MODELS: dict = {}
_LOCK = threading.Lock()


def _model(scene: str, overrides: Sequence[str]):
    """The loaded model of (scene, overrides), once per process (and per dask worker)."""
    key = (scene, tuple(overrides))
    with _LOCK:
        model = _MODELS.get(key)
        if model is None:
            from derive.scene import SceneError, load_scene
            from runtime.model import load_model
            try:
                sc = load_scene(scene, list(overrides))
            except SceneError as exc:
                raise UserError(str(exc)) from None
            model = load_model(sc, list(overrides))
            model.lib  # compile or load from the content-hash cache now, not inside a timed run
            _MODELS[key] = model
        return model


def remember(common: Common, model) -> None:
    """Register an already loaded model (serial runs reuse the caller's)."""
    with _LOCK:
        _MODELS[(common.scene, tuple(common.overrides))] = model


def _init_worker(scene: str, overrides: tuple[str, ...]) -> None:
    _model(scene, overrides)
    import runtime.simulate  # noqa: F401  (import once here, not inside the first timed point)


def point_run(model, spin: float, tilt: float = 0.0, height: float = 0.0, t_end: float = 1.0,
              integrator: str = "dop853", tol: float | None = 1e-9, h: float | None = None,
              p: np.ndarray | None = None, z_s: float | None = None, n_out: int = N_OUT) -> dict:
    """runtime.simulate.simulate from the same pieces (initial state, box, scales, integrator,
    summary), with two differences: the hover height z_s may be given (a scan finds it once per
    mass, not once per point: it costs more than a short run), and the top may start displaced to
    z_0 = z_s (1 + height), at rest vertically; box and checks stay centred on z_s (thesis 3.3.2).
    With height = 0 the result is simulate()'s, number for number (tests/test_scan.py)."""
    from runtime import simulate as sim
    from runtime.integrate import FIXED_STEP, integrate
    pt = model.part("full")
    p = model.p if p is None else p
    pvals = {k: float(v) for k, v in zip(model.manifest["parameters"], p)}
    if z_s is None:
        z_s = sim.hover_height(model, p)
    bx = sim.default_box(pt, z_s)
    if integrator in FIXED_STEP and h is None:
        stiffness = pvals["mu"] * float(model.onaxis(z_s, p)[3])
        h = sim.default_step(spin, pvals, z_s, stiffness)
    x0 = sim.initial_state(pt, z_s * (1.0 + height), spin, tilt, 0.0, p)
    scale = sim.state_scales(pt, z_s, spin, pvals)
    res = integrate(pt, x0, t_end, method=integrator, tol=tol, h=h, p=p, box=bx, n_out=n_out,
                    scale=scale, monitor_energy=integrator in ("dop853", "rk4", "euler", "gauss4",
                                                               "midpoint"))
    return sim.summarize(pt, res, x0, p, z_s, bx, spin, tilt, 0.0, t_end, integrator, tol, h, None)


def run_point(common: Common, task: tuple[int, int, float, float]) -> dict:
    """One grid point (i_spin, j_other, spin, other) -> its survival (a thesis 3.1-3.2 run)."""
    i, j, spin, other = task
    model = _model(common.scene, common.overrides)
    t0 = time.perf_counter()
    p = model.p
    if common.axis == "mass":
        p = model.p.copy()
        p[list(model.manifest["parameters"]).index("m")] = other
    r = point_run(model, spin, tilt=other if common.axis == "tilt" else common.base_tilt,
                  height=other if common.axis == "height" else 0.0, t_end=common.t_end,
                  integrator=common.integrator, tol=common.tol, h=common.h, p=p,
                  z_s=common.hover[j])
    return {"i": i, "j": j, "levitating": bool(r["levitating"]), "t_survived": float(r["t_survived"]),
            "status": r["status"], "rhs_evals": r["rhs_evals"], "wall_s": time.perf_counter() - t0}


def _run_point_packed(args: tuple) -> dict:
    return run_point(*args)


# ----------------------------------------------------------------------------- runners

def _progress(done: int, total: int, t0: float, quiet: bool) -> None:
    if quiet:
        return
    step = max(1, total // 10)
    if done % step == 0 or done == total:
        print(f"levitron scan: {done}/{total} points, {time.perf_counter() - t0:.1f} s",
              file=sys.stderr, flush=True)


def run_serial(common: Common, tasks: Sequence[tuple], quiet: bool = False) -> list[dict]:
    t0 = time.perf_counter()
    out = []
    for k, t in enumerate(tasks, 1):
        out.append(run_point(common, t))
        _progress(k, len(tasks), t0, quiet)
    return out


def run_processes(common: Common, tasks: Sequence[tuple], workers: int,
                  quiet: bool = False) -> list[dict]:
    """Local processes (spawn: no fork of a process holding BLAS threads or a loaded library)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    ctx = multiprocessing.get_context("spawn")
    t0 = time.perf_counter()
    out = []
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                             initargs=(common.scene, tuple(common.overrides))) as ex:
        futures = [ex.submit(run_point, common, t) for t in tasks]
        for k, fut in enumerate(as_completed(futures), 1):
            out.append(fut.result())
            _progress(k, len(tasks), t0, quiet)
    return out


def run_dask(common: Common, tasks: Sequence[tuple], address: str, quiet: bool = False) -> list[dict]:
    """A dask.distributed cluster at `address` (e.g. tcp://host:8786)."""
    try:
        from dask.distributed import Client
    except ImportError:
        raise UserError("--scheduler needs dask.distributed, which is not installed: "
                        "pip install 'levitron[cluster]' (or 'dask[distributed]'), or use --workers N "
                        "for local processes") from None
    try:
        client = Client(address, timeout=20)
    except (OSError, TimeoutError, ValueError) as exc:
        raise UserError(f"cannot reach the dask scheduler at {address!r} ({exc}); start one with "
                        "`dask scheduler` and workers with `dask worker ADDRESS`, or use --workers N"
                        ) from None
    t0 = time.perf_counter()
    try:
        futures = client.map(_run_point_packed, [(common, t) for t in tasks], pure=False)
        out = client.gather(futures)
    finally:
        client.close()
    _progress(len(tasks), len(tasks), t0, quiet)
    return list(out)


# ----------------------------------------------------------------------------- linear theory

def _pvals(model, p: np.ndarray | None = None) -> dict:
    pv = model.p if p is None else p
    return {k: float(v) for k, v in zip(model.manifest["parameters"], pv)}


def linear_interval(model, mass: float | None = None) -> dict:
    """The linear spin interval (thesis 3.3, exact discriminant route) and z_s, for the scene's top
    or one of another mass."""
    from runtime import equilibrium as eqm
    from runtime import linear
    P = _pvals(model)
    m = P["m"] if mass is None else float(mass)
    onaxis = linear.model_onaxis(model)
    res = linear.analyse(onaxis, m, P["g"], P["A"], P["C"], P["mu"], eqm.length_scale(P))
    iv = res.spin_interval
    return {"mass": m, "z_s": res.z_s, "spin_interval": None if iv is None else [float(iv[0]), float(iv[1])],
            "reason": res.reason}


def slow_period(model, mass: float, z_s: float, spin: float) -> float:
    """The longest period of the motion near the relative equilibrium at this spin: the slowest
    transverse mode of the 8-D linearisation after thesis 3.3.5, or the vertical bounce
    2 pi sqrt(m / (mu Phi_3(z_s))) (thesis 3.3.3), whichever is slower."""
    from runtime import linear
    P = _pvals(model)
    ph = np.asarray(model.onaxis(z_s), float)
    periods = []
    k = P["mu"] * ph[3]
    if k > 0:
        periods.append(2 * math.pi * math.sqrt(mass / k))
    J = linear.transverse_matrix(ph[1], ph[2], ph[3], mass, P["A"], P["C"], P["mu"], spin)
    lam = np.linalg.eigvals(J)
    im = np.abs(lam.imag)
    im = im[im > 1e-9 * max(1.0, float(np.abs(lam).max()))]
    if im.size:
        periods.append(2 * math.pi / float(im.min()))
    if not periods:
        raise UserError("no oscillation at the hover height to set a run length from; pass --t-end T")
    return max(periods)


def reference_spin(interval: Sequence[float] | None, spins: np.ndarray) -> float:
    """A spin to measure the slow period at: the geometric mean of the linear interval, else of
    the scanned spin range (else its largest |value|)."""
    if interval is not None:
        return math.sqrt(interval[0] * interval[1])
    lo, hi = float(np.abs(spins).min()), float(np.abs(spins).max())
    if lo > 0:
        return math.sqrt(lo * hi)
    return hi if hi > 0 else 1.0


# ----------------------------------------------------------------------------- the scan

@dataclass
class ScanResult:
    axis: str
    spins: np.ndarray
    others: np.ndarray
    levitating: np.ndarray
    t_survived: np.ndarray
    status: list
    linear: list                  # per value of the other axis: linear_interval dicts
    t_end: float
    t_end_basis: dict
    wall_s: float
    runner: dict
    rhs_evals: int
    cpu_s: float
    extra: dict = field(default_factory=dict)

    def agreement(self) -> float | None:
        """Fraction of grid points where 'levitating' equals 'spin inside the linear interval'."""
        pred = np.zeros_like(self.levitating)
        have = False
        for j, lin in enumerate(self.linear):
            iv = lin.get("spin_interval")
            if iv is not None:
                have = True
                pred[:, j] = (self.spins >= iv[0]) & (self.spins <= iv[1])
        if not have:
            return None
        return float(np.mean(pred == self.levitating))

    def as_dict(self) -> dict:
        scene_lin = self.linear[0] if self.axis != "mass" else self.extra.get("scene_linear")
        return {
            "axes": ["spin", self.axis],
            "grid": {"spin": self.spins.tolist(), self.axis: self.others.tolist()},
            "units": {"spin": UNITS["spin"], self.axis: UNITS[self.axis]},
            "spin_hz": (self.spins / (2 * math.pi)).tolist(),
            "levitating": self.levitating.tolist(),
            "t_survived": self.t_survived.tolist(),
            "status": self.status,
            "fraction_levitating": float(self.levitating.mean()),
            "spin_interval": None if scene_lin is None else scene_lin["spin_interval"],
            "linear": {
                "spin_interval": [lin["spin_interval"] for lin in self.linear],
                "z_s": [lin["z_s"] for lin in self.linear],
                "note": "thesis 3.3 (exact discriminant route), one entry per value of the "
                        f"{self.axis} axis; null where no spin stabilises",
                "agreement": self.agreement(),
            },
            "t_end": self.t_end,
            "t_end_basis": self.t_end_basis,
            "wall_s": self.wall_s,
            "cpu_s": self.cpu_s,
            "rhs_evals": self.rhs_evals,
            "points": int(self.levitating.size),
            "runner": self.runner,
            **self.extra.get("public", {}),
        }


def scan(model, scene_ref: str, overrides: Sequence[str], spins: np.ndarray, axis: str,
         others: np.ndarray, t_end: float | None = None, integrator: str = "dop853",
         tol: float | None = 1e-9, workers: int = 1, scheduler: str | None = None,
         base_tilt: float = BASE_TILT, h: float | None = None, quiet: bool = False) -> ScanResult:
    """Run the map (module docstring). scene_ref/overrides let the workers load the same model."""
    from runtime.simulate import hover_height
    if axis not in AXES:
        raise UserError(f"unknown axis {axis!r}; scan over one of --tilt, --mass, --height")
    spins, others = np.asarray(spins, float), np.asarray(others, float)
    check_axis(axis, others)
    if spins.size * others.size > MAX_POINTS:
        raise UserError(f"{spins.size * others.size} grid points is too many (at most {MAX_POINTS}); "
                        "use fewer points per axis")
    if workers < 1:
        raise UserError(f"--workers {workers} must be at least 1")
    if scheduler is not None and workers != 1:
        raise UserError("pass either --workers N (local processes) or --scheduler ADDRESS (dask), not both")
    if t_end is not None and not (math.isfinite(t_end) and t_end > 0):
        raise UserError(f"--t-end {t_end} must be a positive run length in s, e.g. --t-end 5")
    if not math.isfinite(base_tilt):
        raise UserError("--base-tilt must be a finite angle (rad)")
    t_wall = time.perf_counter()

    # the hover heights (runtime.simulate.hover_height, thesis 3.3.2-3.3.3) and the linear picture
    status_pre: dict[int, str] = {}
    names = list(model.manifest["parameters"])
    if axis == "mass":
        lin, hover = [], []
        for j, m in enumerate(others):
            p = model.p.copy()
            p[names.index("m")] = m
            try:
                hover.append(hover_height(model, p))
            except UserError:
                hover.append(None)
                status_pre[j] = "no_hover_height"
            lin.append(linear_interval(model, m))
        scene_lin = linear_interval(model)
    else:
        lin = [linear_interval(model)] * len(others)
        hover = [hover_height(model)] * len(others)
        scene_lin = lin[0]

    # the default run length: PERIODS slow periods of the scene's top (mass scan: the median over
    # the masses that some spin stabilises, else over those that hover)
    if t_end is None:
        cands = [li for j, li in enumerate(lin) if j not in status_pre and li["z_s"] is not None]
        good = [li for li in cands if li["spin_interval"] is not None]
        if axis != "mass":
            pool = cands
        else:
            pool = good or cands
        if not pool:
            raise UserError("no value of the scan has a stable hover height to set a run length "
                            "from; pass --t-end T or change the --mass range (see `levitron equilibrium`)")
        rows = sorted((slow_period(model, li["mass"], li["z_s"], reference_spin(li["spin_interval"], spins)),
                       reference_spin(li["spin_interval"], spins), li["mass"]) for li in pool)
        T, ref, m_ref = rows[(len(rows) - 1) // 2]
        t_end = PERIODS * T
        basis = {"periods": PERIODS, "slow_period_s": T, "reference_spin": ref, "mass": m_ref,
                 "note": "default: periods of the slowest motion at the relative equilibrium "
                         "(transverse modes, thesis 3.3.5, or the vertical bounce, 3.3.3)"}
    else:
        basis = {"given": True}

    common = Common(scene_ref, tuple(overrides), axis, float(t_end), integrator, tol,
                    float(base_tilt), tuple(hover), h)
    tasks = [(i, j, float(s), float(o)) for i, s in enumerate(spins) for j, o in enumerate(others)
             if j not in status_pre]
    if scheduler is not None:
        runner = {"kind": "dask", "scheduler": scheduler}
        results = run_dask(common, tasks, scheduler, quiet)
    elif workers > 1 and len(tasks) > 1:
        n = min(workers, len(tasks))
        runner = {"kind": "processes", "workers": n}
        results = run_processes(common, tasks, n, quiet)
    else:
        runner = {"kind": "serial", "workers": 1}
        remember(common, model)
        results = run_serial(common, tasks, quiet)

    shape = (spins.size, others.size)
    lev = np.zeros(shape, bool)
    ts = np.zeros(shape)
    status = [["" for _ in others] for _ in spins]
    for i in range(spins.size):
        for j in status_pre:
            status[i][j] = status_pre[j]
    rhs = 0
    cpu = 0.0
    for r in results:
        lev[r["i"], r["j"]] = r["levitating"]
        ts[r["i"], r["j"]] = r["t_survived"]
        status[r["i"]][r["j"]] = r["status"]
        rhs += int(r["rhs_evals"] or 0)
        cpu += r["wall_s"]
    return ScanResult(axis, spins, others, lev, ts, status, lin, float(t_end), basis,
                      time.perf_counter() - t_wall, runner, rhs, cpu,
                      extra={"scene_linear": scene_lin,
                             "public": {"integrator": integrator, "tol": tol,
                                        "base_tilt": base_tilt if axis != "tilt" else None}})


# ----------------------------------------------------------------------------- the picture

def _edges(v: np.ndarray) -> np.ndarray:
    if v.size == 1:
        d = abs(v[0]) * 0.05 or 0.5
        return np.array([v[0] - d, v[0] + d])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def draw(res: ScanResult, path: str | Path, title: str = "") -> Path:
    """The map (thesis fig. 3.8): colour = t_survived / t_end (1 = levitating, marked with dots)
    over spin (x) and the other axis (y); the linear spin interval as vertical lines (for a mass
    scan, one pair per mass row: it moves with the mass)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    path = Path(path)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    frac = (res.t_survived / res.t_end).T
    fig, ax = plt.subplots(figsize=(8, 5.5))
    mesh = ax.pcolormesh(_edges(res.spins), _edges(res.others), frac, cmap="viridis", vmin=0, vmax=1,
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label="t_survived / t_end  (1 = levitating)")
    S, O = np.meshgrid(res.spins, res.others, indexing="ij")
    ax.plot(S[res.levitating], O[res.levitating], "w.", ms=4, label="levitating")
    los = [li["spin_interval"][0] if li["spin_interval"] else np.nan for li in res.linear]
    his = [li["spin_interval"][1] if li["spin_interval"] else np.nan for li in res.linear]
    if res.axis == "mass":   # the interval moves with the mass: vertical lines per row
        ye = _edges(res.others)
        label = "linear stability interval (thesis 3.3)"
        for j in range(res.others.size):
            if np.isfinite(los[j]):
                ax.vlines([los[j], his[j]], ye[j], ye[j + 1], colors="r", lw=1.5, label=label)
                label = None
    elif np.isfinite(los[0]):
        ax.axvline(los[0], color="r", lw=1.5, label="linear stability interval (thesis 3.3)")
        ax.axvline(his[0], color="r", lw=1.5)
    ax.set_xlim(_edges(res.spins)[[0, -1]])
    ax.set_xlabel("spin (rad/s)")
    ax.set_ylabel(f"{res.axis} ({UNITS[res.axis]})")
    ax.set_title(title or f"stability map: {res.axis} vs spin, t_end = {res.t_end:.3g} s")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def values_of(spec: str | None, label: str) -> np.ndarray | None:
    return None if spec is None else parse_range(spec, label)


def pick_axis(specs: dict[str, str | None]) -> tuple[str, str]:
    """Exactly one of --tilt/--mass/--height."""
    given = [(k, v) for k, v in specs.items() if v is not None]
    if len(given) != 1:
        names = ", ".join("--" + k for k, _ in given) if given else "none"
        raise UserError(f"pass exactly one of --tilt, --mass, --height as the second axis (got {names}), "
                        "e.g. --tilt 0:0.3:10")
    return given[0]
