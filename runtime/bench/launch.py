"""`levitron bench SCENE --kind launch`: the cost of a real launch.

Two figures for a scene in air (derive/friction.py): the wall time of one long flight
(FULL["flight"] s, one core, the generated C through runtime.simulate.run, the summary included)
and of a launch Monte Carlo (FULL["n"] launches of FULL["t_end"] s each on FULL["workers"]
processes, runtime/scan/launch_odds.py), each the minimum of FULL["repeats"]. Writes launch.json,
launch.csv and the Monte Carlo's histogram.
"""
from __future__ import annotations

import csv
import json
import time
from pathlib import Path


from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.simulate.run import simulate
from levitron.runtime.ui.atomic import open_text, write_text


def measure(model, flight: float, n: int, t_end: float, workers: int, repeats: int) -> dict:
    from levitron.runtime.physics.stability.analysis import stability_of
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
        res = mc.monte_carlo(model, {}, n=n, seed=0, t_end=t_end, workers=workers, quiet=True)
        best_mc = min(best_mc, time.perf_counter() - t0)
    return {"scene": model.ref.scene, "spin": spin,
            "flight": {"t_end": flight, "wall_s": best_flight, "integration_wall_s": run["wall_s"],
                       "flight_time": run["flight"]["flight_time"], "t_cross": run["flight"]["t_cross"],
                       "rhs_evals": run["rhs_evals"]},
            "monte_carlo": {"n": n, "t_end": t_end, "workers": workers, "wall_s": best_mc,
                            "probability": res["probability"], "probability_ci95": res["probability_ci95"],
                            "ranking": [e["input"] for e in res["ranking"]]},
            "result": res}


FULL = {"flight": 300.0, "n": 1000, "t_end": 60.0, "workers": 2, "repeats": 2}
QUICK = {"flight": 20.0, "n": 8, "t_end": 2.0, "workers": 1, "repeats": 1}


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): one long flight and a Monte Carlo (FULL, or
    QUICK for the tests), written to out/launch.json, launch.csv and launch_histogram.png."""
    o = QUICK if quick else FULL
    r = measure(model, o["flight"], o["n"], o["t_end"], o["workers"], o["repeats"])
    out.mkdir(parents=True, exist_ok=True)
    res = r.pop("result")
    write_text(out / "launch.json", option="«out»", text=json.dumps(r, indent=2) + "\n")
    with open_text(out / "launch.csv", "«out»", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["what", "size", "workers", "wall_s"])
        w.writerow([f"one flight of {o['flight']:g} s", 1, 1, f"{r['flight']['wall_s']:.4g}"])
        w.writerow([f"Monte Carlo, launches of {o['t_end']:g} s", o["n"], o["workers"],
                    f"{r['monte_carlo']['wall_s']:.4g}"])
    res.plot(out / "launch_histogram.png")
    r["files"] = [str(out / f) for f in ("launch.json", "launch.csv", "launch_histogram.png")]
    r["headline"] = (f"a {o['flight']:g} s flight in {r['flight']['wall_s']:.3g} s wall; {o['n']} launches of "
                     f"{o['t_end']:g} s on {o['workers']} worker(s) in {r['monte_carlo']['wall_s']:.3g} s")
    return r
