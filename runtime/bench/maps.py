"""The maps part of the bench: how fast `levitron scan` maps a scene, and what the
integration costs beyond the right-hand-side calls it makes (thesis 3.1-3.3, fig. 3.8).

The map: spin x tilt, N x N points, the spins from SPIN_BELOW times the lower end of the scene's
linear stability interval to SPIN_ABOVE times its upper end (thesis 3.3, runtime.physics.stability.analysis), the
tilts from MAX_TILT / N to MAX_TILT rad (no tilt-0 row: it would test nothing), each point one run
of the full model from the hover height z_s over t_end (default: the scan's own, PERIODS slow
periods; runtime/scan/stability_map.py). It is run serially and on 2 local worker processes
(runtime/scan/runners.py), through the C chunk driver (runtime/csrc/scan_driver.c), and a sub-grid
also through runtime.simulate.run's Python path (one `integrate` call with dense output and energy
monitor per point: the way maps were made before).

Per run: points, wall_s, points_per_s = points / wall_s (the whole scan call: hover height, linear
interval, worker start, integration), cpu_s (CPU time of the threads that ran the chunks),
cpu_total_s (this process and its finished children, the whole call), rhs_evals, and
cpu_over_rhs = cpu_s / (rhs_evals * rhs_ns): the integration's CPU time over the time its
right-hand-side calls take, where rhs_ns is the cost of one call of the generated rhs timed in C
(lev_time_fn, the median of RHS_REPEATS loops) at a mid-map state, measured before and after the
runs (`rhs_ns_before_after`; the mean of the two is used: on a shared machine it drifts).
`same_map` says whether every run gave the serial run's status and survival time point for point.

The CLI rows run the same map through `levitron scan` in a fresh process (engine "cli": wall_s is
the whole command, process start, imports, model loading, workers and the JSON output included),
on 1 and 2 workers; `cli_over_driver` is the CLI's wall time over the in-process driver's on the
same number of workers (the goal: at most 1.15), and the CLI's map enters `same_map`.

heyoka's batch mode (the `[bench]` extra; runtime/bench/heyoka.py batch_map: one SIMD lane per
point, terminal events on the box, on the same lowered equations) runs the HEYOKA_N x HEYOKA_N
sub-grid of the map on one core at the tolerances HEYOKA_TOLS, loose to tight, until its
levitating/falling verdict equals the C driver's at every point of the sub-grid: that tolerance is
`heyoka_batch.matched_tol` (matched accuracy), and its points/s stands beside the C driver's on
the same sub-grid (`heyoka_batch.c_points_per_s`, serial). heyoka integrates states scaled by the
median spin's state scales, one vector for all points (its tolerance is per component), where the
C driver scales each point's own; compiles are timed apart and cached on disk.

The machine's speed drifts by up to 30% over tens of seconds (a shared virtual machine), and the
two figures of cpu_over_rhs are taken a minute apart, so the bench also measures it matched:
`matched` runs a sub-grid (every MATCHED_STRIDE-th spin and tilt) serially, MATCHED_SPINS spins
per scan call, and times the rhs (lev_time_fn, the median of MATCHED_REPEATS loops) just before
and after each call; cpu_over_rhs = sum cpu_s / sum (rhs_evals * the mean of the two).

    levitron bench SCENE --kind maps [--quick] [--out DIR]

--quick: a small map (QUICK_N x QUICK_N, one slow period per point) in a few seconds.
"""
from __future__ import annotations

import json
import resource
import statistics
from pathlib import Path

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui.atomic import write_text

SPIN_BELOW, SPIN_ABOVE = 0.5, 1.25   # the spin range around the linear interval [lo, hi]
MAX_TILT = 0.2                       # rad
FULL_N, QUICK_N = 100, 6             # points per axis
PYTHON_N = 20                        # points per axis of the Python-path sub-grid (full bench)
RHS_REPEATS, RHS_REPS = 5, 200_000   # lev_time_fn: loops and calls per loop
WORKERS = (1, 2)
MATCHED_STRIDE, MATCHED_SPINS, MATCHED_REPEATS = 2, 5, 3
HEYOKA_N = 40                        # points per axis of heyoka's sub-grid (quick: the whole map)
HEYOKA_TOLS = (1e-9, 1e-10, 1e-11, 1e-12, 1e-13)


def map_axes(model, n: int) -> tuple[np.ndarray, np.ndarray, dict]:
    """The spin and tilt values of the bench's map (module docstring) and the linear interval
    (runtime.scan.physics.linear_interval)."""
    from levitron.runtime.scan.physics import linear_interval
    lin = linear_interval(model)
    iv = lin["spin_interval"]
    if iv is None:
        raise UserError(f"scene '{model.scene.name}': no spin stabilises its top (thesis 3.3), so a "
                        "map has no interval to centre on; bench a scene whose `levitron stability` "
                        "gives a spin interval")
    # tilts from MAX_TILT / n: a tilt-0 row lies on the invariant set and tests nothing (thesis 3.2.1)
    return (np.linspace(SPIN_BELOW * iv[0], SPIN_ABOVE * iv[1], n),
            np.linspace(MAX_TILT / n, MAX_TILT, n), lin)


def rhs_ns(model, spins: np.ndarray, tilts: np.ndarray, repeats: int = RHS_REPEATS) -> float:
    """ns per call of the full rhs (lev_time_fn in C) at the start of a mid-map point: the median
    of `repeats` loops of RHS_REPS calls."""
    from levitron.runtime.integrate.run import time_fn_ns
    from levitron.runtime.scan.points import point_setup
    su = point_setup(model, float(np.median(spins)), float(np.median(tilts)))
    fn = su.part.c_function("rhs")
    return statistics.median(time_fn_ns(model.lib, fn, su.x0, su.p, su.x0.size, RHS_REPS)
                             for _ in range(repeats))


def matched(model, spins, tilts, t_end) -> dict:
    """cpu_over_rhs with the rhs timed next to every scan call (module docstring)."""
    from levitron.runtime.scan import stability_map as sc
    spins, tilts = spins[::MATCHED_STRIDE], tilts[::MATCHED_STRIDE]
    cpu = rhs_cost = 0.0
    evals = 0
    for k in range(0, spins.size, MATCHED_SPINS):
        before = rhs_ns(model, spins, tilts, MATCHED_REPEATS)
        res = sc.scan(model, spins[k:k + MATCHED_SPINS], "tilt", tilts,
                      t_end=t_end, workers=1, quiet=True, engine="c")
        after = rhs_ns(model, spins, tilts, MATCHED_REPEATS)
        cpu += res.cpu_s
        evals += res.rhs_evals
        rhs_cost += res.rhs_evals * 0.5 * (before + after) * 1e-9
    return {"grid": [int(spins.size), int(tilts.size)], "cpu_s": cpu, "rhs_evals": evals,
            "rhs_ns": rhs_cost / evals * 1e9 if evals else None,
            "cpu_over_rhs": cpu / rhs_cost if rhs_cost else None}


def _cpu_total() -> float:
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def one_run(model, spins, tilts, t_end, workers: int,
            engine: str) -> tuple[dict, object]:
    """One scan and its row (module docstring; rhs_ns and cpu_over_rhs are added by `run`)."""
    from levitron.runtime.scan import stability_map as sc
    cpu0 = _cpu_total()
    res = sc.scan(model, spins, "tilt", tilts, t_end=t_end, workers=workers,
                  quiet=True, engine=engine)
    cpu_total = _cpu_total() - cpu0
    points = int(res.levitating.size)
    row = {"engine": engine, "workers": workers, "grid": [int(spins.size), int(tilts.size)],
           "points": points, "t_end": res.t_end, "wall_s": res.wall_s,
           "points_per_s": points / res.wall_s, "cpu_s": res.cpu_s, "cpu_total_s": cpu_total,
           "rhs_evals": res.rhs_evals, "fraction_levitating": float(res.levitating.mean())}
    return row, res


def cli_run(ref, spins, tilts, t_end: float, workers: int) -> tuple[dict, object]:
    """The same map through `levitron scan` in a fresh process (module docstring): its row, and
    its map (status, t_survived) for the point-for-point check. ref: the model's SceneRef."""
    scene_ref, overrides = ref
    import subprocess
    import sys
    import time
    from types import SimpleNamespace
    script = Path(sys.executable).with_name("levitron")
    cmd = [str(script)] if script.exists() else [sys.executable, "-m", "levitron.runtime"]
    rng = lambda a: f"{float(a[0])!r}:{float(a[-1])!r}:{a.size}"    # repr: the same doubles back
    cmd += ["scan", scene_ref, "--spin", rng(spins), "--tilt", rng(tilts), "--t-end", repr(float(t_end)),
            "--workers", str(workers), "--json", "--quiet"]
    for kv in overrides:
        cmd += ["--set", kv]
    t0 = time.perf_counter()
    res = subprocess.run(cmd, check=False, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if res.returncode != 0:
        raise UserError(f"bench maps: `levitron scan` failed: {res.stderr.strip()[-500:]}")
    out = json.loads(res.stdout)
    m = SimpleNamespace(status=out["status"], t_survived=np.array(out["t_survived"], float))
    lev = np.array(out["levitating"], bool)
    row = {"engine": "cli", "workers": workers, "grid": [int(spins.size), int(tilts.size)],
           "points": int(lev.size), "t_end": out["t_end"], "wall_s": wall,
           "points_per_s": lev.size / wall, "scan_wall_s": out["wall_s"], "cpu_s": out["cpu_s"],
           "rhs_evals": out["rhs_evals"], "fraction_levitating": float(lev.mean())}
    return row, m


def heyoka_batch(model, spins, tilts, t_end: float, quick: bool) -> dict:
    """heyoka's batch mode on a sub-grid beside the C driver on it (module docstring); a note
    instead when heyoka is not installed."""
    from levitron.runtime.bench import heyoka as bench_heyoka
    if not bench_heyoka.available():
        return {"note": "heyoka not installed: pip install '.[bench]'"}
    import time

    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.scan import stability_map as sc
    from levitron.runtime.scan.points import point_setup
    k = spins.size if quick else min(HEYOKA_N, spins.size)
    idx = np.unique(np.linspace(0, spins.size - 1, k).round().astype(int))
    sp, tl = spins[idx], tilts[np.unique(np.linspace(0, tilts.size - 1, k).round().astype(int))]
    ours = sc.scan(model, sp, "tilt", tl, t_end=t_end, workers=1, quiet=True)
    z_s = hover_height(model)
    memo: dict = {}
    setups = [point_setup(model, float(s), float(t), z_s=z_s, memo=memo) for s in sp for t in tl]
    want = np.array([ours.status[i][j] == "completed" for i in range(sp.size) for j in range(tl.size)])
    mid = point_setup(model, float(np.median(sp)), float(np.median(tl)), z_s=z_s, memo=memo)
    scale, box = mid.scale, setups[0].box
    X0 = np.array([su.x0 for su in setups])
    P = np.array([su.p for su in setups])
    from levitron.derive.emit.heyoka import lowered_rhs, system
    built: list = []

    def make_sys():
        if not built:
            built.append(system(lowered_rhs(model.scene, "full"), scale))
        return built[0]

    rows, matched = [], None
    for tol in HEYOKA_TOLS[:2] if quick else HEYOKA_TOLS:
        key = bench_heyoka.cache_key(**bench_heyoka.expressions_key(model, "full"), part="full", kind="batch_map",
                                     scale=[float(v).hex() for v in scale], tol=float(tol).hex(),
                                     box=[box.iz, box.z_lo.hex(), box.z_hi.hex(), box.ix, box.iy,
                                          float(box.r_max).hex()])
        t0 = time.perf_counter()
        r = bench_heyoka.batch_map(make_sys, X0, P, box, scale, t_end, tol, key=key)
        agree = int(np.sum(r["levitating"] == want))
        rows.append({"tol": tol, "points": int(want.size), "wall_s": r["wall_s"],
                     "points_per_s": want.size / r["wall_s"], "compile_s": r["compile_s"],
                     "compile_cached": r["compile_cached"], "batch_size": r["batch_size"],
                     "agree_points": agree, "same_map": agree == want.size,
                     "call_s": time.perf_counter() - t0})
        if agree == want.size:
            matched = tol
            break
    return {"grid": [int(sp.size), int(tl.size)], "t_end": t_end, "rows": rows, "matched_tol": matched,
            "c_points_per_s": want.size / ours.wall_s, "c_wall_s": ours.wall_s,
            "points_per_s_at_matched": next((r["points_per_s"] for r in rows if r["tol"] == matched), None)}


def _same(a, b, rows=None, cols=None) -> bool:
    """Status and survival time of b equal a's on the points of b (a sub-grid of a by index)."""
    rows = range(len(b.status)) if rows is None else rows
    cols = range(len(b.status[0])) if cols is None else cols
    return all(a.status[i][j] == b.status[r][c] and a.t_survived[i, j] == b.t_survived[r, c]
               for r, i in enumerate(rows) for c, j in enumerate(cols))


def run(model, n: int | None = None, t_end: float | None = None,
        quick: bool = False, python_n: int | None = None) -> dict:
    """The bench's rows (module docstring): the C driver at 1 and 2 workers on the n x n map, and the
    Python path serially on a python_n x python_n sub-grid of it (every k-th spin and tilt)."""
    from levitron.runtime.scan.physics import reference_spin, slow_period
    n = n or (QUICK_N if quick else FULL_N)
    python_n = min(n, python_n or (QUICK_N if quick else PYTHON_N))
    if n < 2:
        raise UserError(f"«n={n}»: a map needs at least 2 points per axis")
    spins, tilts, lin = map_axes(model, n)
    if t_end is None and quick:        # one slow period (the scan's default is PERIODS of them)
        t_end = slow_period(model, lin["mass"], lin["z_s"], reference_spin(lin["spin_interval"], spins))
    ns_before = rhs_ns(model, spins, tilts)
    rows, maps = [], []
    for w in WORKERS:
        maps.append(one_run(model, spins, tilts, t_end, w, "c"))
    clis = [cli_run(model.ref, spins, tilts, maps[0][1].t_end, w) for w in WORKERS]
    idx = np.unique(np.linspace(0, n - 1, python_n).round().astype(int))
    py = one_run(model, spins[idx], tilts[idx], maps[0][1].t_end, 1, "python")
    ns_after = rhs_ns(model, spins, tilts)
    ns = 0.5 * (ns_before + ns_after)
    match = matched(model, spins, tilts, maps[0][1].t_end)
    hb = heyoka_batch(model, spins, tilts, maps[0][1].t_end, quick)
    for row, _ in maps + [py] + clis:
        row["rhs_ns"] = ns
        row["cpu_over_rhs"] = row["cpu_s"] / (row["rhs_evals"] * ns * 1e-9) if row["rhs_evals"] else None
        rows.append(row)
    py_row = rows[len(maps)]
    cli_over = {str(c["workers"]): c["wall_s"] / d["wall_s"] for (c, _), (d, _) in zip(clis, maps)}
    maps, py = [m for _, m in maps], py[1]
    same = (all(_same(maps[0], m) for m in maps[1:]) and _same(maps[0], py, idx, idx)
            and all(_same(maps[0], m) for _, m in clis))
    return {
        "scene": model.scene.name,
        "map": {"axes": ["spin", "tilt"], "spin": [float(spins[0]), float(spins[-1]), n],
                "tilt": [0.0, MAX_TILT, n], "t_end": maps[0].t_end},
        "rhs_ns": ns,
        "rhs_ns_before_after": [ns_before, ns_after],
        "rows": rows,
        "same_map": bool(same),
        "speedup_2_workers": rows[1]["points_per_s"] / rows[0]["points_per_s"],
        "cli_over_driver": cli_over,
        "cpu_over_rhs": {"c_driver": rows[0]["cpu_over_rhs"], "python_path": py_row["cpu_over_rhs"],
                         "c_driver_matched": match["cpu_over_rhs"]},
        "matched": match,
        "heyoka_batch": hb,
        "note": __doc__.split("\n\n")[2].replace("\n", " "),
    }


def _heyoka_headline(hb: dict) -> str:
    if hb.get("matched_tol") is None:
        return "; heyoka batch: " + hb.get("note", "no tolerance tried gave the same map")
    return (f"; heyoka batch at tol {hb['matched_tol']:g} (same map on its {hb['grid'][0]} x "
            f"{hb['grid'][1]} sub-grid): {hb['points_per_s_at_matched']:.0f} points/s against "
            f"{hb['c_points_per_s']:.0f} for the C driver there")


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): the rows of `run`, written to out/bench_maps.json."""
    res = run(model, quick=quick)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "bench_maps.json"
    write_text(path, option="«out»", text=json.dumps(res, indent=1) + "\n")
    r0 = res["rows"][0]
    res["headline"] = (f"{res['map']['spin'][2]} x {res['map']['tilt'][2]} map: {r0['points_per_s']:.0f} points/s "
                       f"on 1 worker, {res['rows'][1]['points_per_s']:.0f} on 2; cpu/rhs "
                       f"{res['cpu_over_rhs']['c_driver']:.2f}; the CLI's wall over the driver's: "
                       + ", ".join(f"{v:.2f} on {w}" for w, v in res["cli_over_driver"].items())
                       + f"; same map on every path: {res['same_map']}" + _heyoka_headline(res["heyoka_batch"]))
    res["files"] = [str(path)]
    return res
