"""`python -m runtime.bench_launch SCENE --out reports/launch`: the cost of a real launch.

Two figures for a scene in air (derive/friction.py): the wall time of one long flight
(`--flight` s, one core, the generated C through runtime.simulate, the summary included) and of a
launch Monte Carlo (`--n` launches of `--t-end` s each on `--workers` processes, runtime/launch.py),
each the minimum of `--repeats`. Writes launch.json, launch.csv and the Monte Carlo's histogram.
"""
from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

from derive.scene import load_scene

from . import launch as mc
from .human import Units
from .model import load_model
from .simulate import simulate


def measure(scene: str, flight: float, n: int, t_end: float, workers: int, repeats: int) -> dict:
    model = load_model(load_scene(scene))
    ref = str(model.scene.path.resolve())
    from .stability import stability_of
    lo, hi = stability_of(model).spin_interval
    spin = (lo * hi) ** 0.5
    simulate(model, spin=spin, t_end=1.0)                       # warm: compile, load, verify
    best_flight, run = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        run = simulate(model, spin=spin, t_end=flight)
        best_flight = min(best_flight, time.perf_counter() - t0)
    best_mc, res = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = mc.monte_carlo(model, ref, [], {}, n=n, seed=0, t_end=t_end, workers=workers, quiet=True)
        best_mc = min(best_mc, time.perf_counter() - t0)
    return {"scene": scene, "spin": spin,
            "flight": {"t_end": flight, "wall_s": best_flight, "integration_wall_s": run["wall_s"],
                       "flight_time": run["flight"]["flight_time"], "t_cross": run["flight"]["t_cross"],
                       "rhs_evals": run["rhs_evals"]},
            "monte_carlo": {"n": n, "t_end": t_end, "workers": workers, "wall_s": best_mc,
                            "probability": res["probability"], "probability_ci95": res["probability_ci95"],
                            "ranking": [e["input"] for e in res["ranking"]]},
            "result": res}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?", default="thesis_air")
    ap.add_argument("--out", default="reports/launch")
    ap.add_argument("--flight", type=float, default=300.0)
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--t-end", type=float, default=60.0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="a 20 s flight and 8 launches of 2 s (tests)")
    a = ap.parse_args(argv)
    if a.quick:
        a.flight, a.n, a.t_end, a.workers, a.repeats = 20.0, 8, 2.0, 1, 1
    r = measure(a.scene, a.flight, a.n, a.t_end, a.workers, a.repeats)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    res = r.pop("result")
    (out / "launch.json").write_text(json.dumps(r, indent=2) + "\n")
    with open(out / "launch.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["what", "size", "workers", "wall_s"])
        w.writerow([f"one flight of {a.flight:g} s", 1, 1, f"{r['flight']['wall_s']:.4g}"])
        w.writerow([f"Monte Carlo, launches of {a.t_end:g} s", a.n, a.workers,
                    f"{r['monte_carlo']['wall_s']:.4g}"])
    mc.draw(res, out / "launch_histogram.png", Units.of_scene(load_scene(a.scene)), a.scene)
    print(json.dumps({k: r[k] for k in ("flight", "monte_carlo")}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
