"""`levitron bench SCENE --quick` runs the scene it is given (docs/contract.md `bench`): its own top, from
its own hover height, at the geometric mean of its stable spin interval; on every scene of scenes/,
and a clear one-line error exactly where the scene's top has no stable interval.
Speed is measured, not asserted: benchmarks are not timed tests."""
from __future__ import annotations

import csv
import json
import math

import pytest

from levitron.scene.load import load_scene
from levitron.scene.paths import SCENES_DIR
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.bench.work_precision import ROW_KEYS
from levitron.runtime.physics.stability.analysis import stability_of

SCENES = [p.stem for p in sorted(SCENES_DIR.glob("*.toml"))]


@pytest.mark.parametrize("name", SCENES)
def test_bench_quick_on_every_scene(name, tmp_path, capsys):
    from levitron.runtime.cli.main import main
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene(name))
    lin = stability_of(model)
    rc = main(["bench", name, "--quick", "--out", str(tmp_path), "--json"])
    out, err = capsys.readouterr()
    if "full" in model.parts and lin.spin_interval is None:
        # the scene's top has no stable interval (the thesis's own top): one clear line, no files
        assert rc == 2 and out == ""
        assert len(err.strip().splitlines()) == 1 and "no stable spin interval" in err, err
        assert "Traceback" not in err and not list(tmp_path.iterdir())
        return
    assert rc == 0, err
    res = json.loads(out)
    su = res["setup"]
    # the scene's own top at its own height, spinning inside its own interval
    assert su["z_s"] == eqm.hover_height(model)
    if lin.spin_interval is not None:
        lo, hi = lin.spin_interval
        assert su["spin"] == pytest.approx(math.sqrt(lo * hi), rel=1e-12) and lo < su["spin"] < hi
    else:                           # a reduced-only model: the spin does not enter its motion
        assert "full" not in model.parts and su["spin"] > 0
    assert su["t_end"] == pytest.approx(su["spin_periods"] * 2 * math.pi / su["spin"], rel=1e-12)
    rows = res["rows"]
    assert {r["model"] for r in rows} == set(model.parts) & {"reduced", "full"}
    assert {r["backend"] for r in rows} == {"c", "casadi", "scipy"}
    for r in rows:
        assert set(ROW_KEYS) <= set(r)
        assert r["wall_s"] > 0
        assert r["status"] == "completed" and math.isfinite(r["error"]), r
    for part in set(model.parts) & {"reduced", "full"}:
        with open(tmp_path / f"bench_{part}.csv") as fh:
            table = list(csv.DictReader(fh))
        assert list(table[0])[:len(ROW_KEYS)] == list(ROW_KEYS)
        assert len(table) == sum(r["model"] == part for r in rows)
        data = json.loads((tmp_path / f"bench_{part}.json").read_text())
        # the reference is an order tighter than the finest bound of the cheapest-run table (1e-13)
        assert data["reference_check"] < 1e-14
        if part == "reduced":       # a second method: z, p_z to round-off; zeta the formula's bias
            d = dict(zip(data["states"], data["reference_vs_taylor"]))
            assert max(d["z"], d["p_z"], d["p_zeta"]) < 1e-14 and d["zeta"] < 5e-13, d
        assert (tmp_path / f"bench_{part}.png").stat().st_size > 5000
        # the per-call race: the prepared run (Study.propagator) beside integrate()'s general path
        calls = data["per_call"]
        with open(tmp_path / f"bench_per_call_{part}.csv") as fh:
            assert {r["contestant"] for r in csv.DictReader(fh)} == set(calls["contestants"])
        if part == "reduced":          # (the full model's quick sweep may miss the bound)
            assert {"dop853", "taylor"} <= set(calls["contestants"])     # the quick sweep's methods
        if calls["contestants"]:
            ours = calls["ours"]
            assert ours["error"] <= calls["bound"] and ours["integrator"] in ("dop853", "vern9", "taylor")
            assert 0 < ours["propagator_s"] < ours["integrate_s"] and ours["c_call_s"] > 0
    goals = json.loads((tmp_path / "bench_goals.json").read_text())
    if "full" in model.parts:
        assert goals["full_rhs_ns"] > 0 and goals["full_rhs_ops"] > 0
        lr = goals["long_run"]
        assert lr["gauss4"]["status"] == lr["rk4"]["status"] == "completed"


def test_every_kind_of_scene_is_benched():
    """Not vacuous: most scenes have a stable interval and are benched, one is reduced-only."""
    from levitron.runtime.model.load import load_model
    ran = []
    for name in SCENES:
        model = load_model(load_scene(name))
        if "full" not in model.parts or stability_of(model).spin_interval is not None:
            ran.append(name)
    assert len(ran) >= 4 and "reduced_only" in ran


def test_bench_errors_shrink_with_tolerance():
    """A sanity check of the error measure on the quick rows: tighter tolerance or smaller step
    gives a smaller error for DOP853 and RK4 (the reference is not one of the rows)."""
    from levitron.runtime.bench.work_precision import bench_model
    from levitron.runtime.model.load import load_model
    res = bench_model(load_model(load_scene("thesis_stable")), "full", quick=True)
    by = {}
    for r in res["rows"]:
        by.setdefault(r["integrator"], []).append(r["error"])
    assert by["dop853"][1] < 1e-3 * by["dop853"][0]
    assert by["rk4"][1] < 1e-3 * by["rk4"][0]
    assert all(math.isfinite(e) for e in by["scipy-dop853"] + by["cvodes"])


def test_cheapest_by_bound_picks_the_fastest_run_within_each_bound():
    from levitron.runtime.bench.work_precision import BOUNDS, cheapest_by_bound
    rows = [{"backend": "c", "integrator": "dop853", "tol": 1e-6, "error": 3e-6, "wall_s": 1.0},
            {"backend": "c", "integrator": "dop853", "tol": 1e-9, "error": 2e-9, "wall_s": 2.0},
            {"backend": "c", "integrator": "rk4", "tol": None, "error": 5e-8, "wall_s": 1.5},
            {"backend": "heyoka", "integrator": "taylor", "tol": 1e-9, "error": 4e-10, "wall_s": 3.0},
            {"backend": "scipy", "integrator": "scipy-dop853", "tol": 1e-6, "error": math.inf,
             "wall_s": 0.1}]
    table = {r["bound"]: r for r in cheapest_by_bound(rows)}
    assert set(table) == set(BOUNDS)
    assert table[1e-5]["c"]["wall_s"] == 1.0                     # dop853 at 3e-6 is the cheapest
    assert table[1e-7]["c"]["integrator"] == "rk4"               # 5e-8: rk4 beats dop853 at 2e-9
    assert table[1e-8]["c"]["wall_s"] == 2.0
    assert table[1e-9]["heyoka"]["wall_s"] == 3.0 and table[1e-10]["heyoka"] is None
    assert all(table[b]["scipy"] is None for b in BOUNDS)        # a failed run (inf) is never cheapest
    assert all(table[b]["casadi"] is None for b in BOUNDS)


def test_heyoka_backend_integrates_the_same_problem():
    """heyoka (optional extra `bench`) on the same lowered equations, parameters, initial state and
    error measure as the C rows: its error against the C reference follows its tolerance."""
    pytest.importorskip("heyoka")
    from levitron.runtime.bench import work_precision as bench
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene("thesis_stable"))
    su = bench.setup(model)
    part, x0, scale = bench.start(model, "reduced", su)
    x_ref, _ = bench.reference(part, x0, su, scale)
    rows = bench.heyoka_rows(model, "reduced", x0, su, scale, x_ref, 1, tols=(1e-6, 1e-11))
    assert [r["backend"] for r in rows] == ["heyoka", "heyoka"]
    assert all(r["status"] == "completed" and r["compile_s"] > 0 and r["steps"] > 0 for r in rows)
    assert rows[0]["error"] < 1e-4 and rows[1]["error"] < 1e-9
    assert rows[1]["error"] < rows[0]["error"]


def test_every_bench_kind_is_a_module_with_the_protocol():
    """The benchmarks' one seam (runtime/bench/kinds.py): each registered kind names a module with
    bench(model, out, quick) and scenes that exist."""
    import importlib
    import inspect

    from levitron.scene.load import find_scene_file
    from levitron.runtime.bench.kinds import KINDS
    for kind in KINDS.values():
        fn = importlib.import_module(kind.module).bench
        assert list(inspect.signature(fn).parameters) == ["model", "out", "quick"]
        assert kind.scenes and all(find_scene_file(s) for s in kind.scenes)


_OSCILLATOR_RUN = """
import sys
import numpy as np
import heyoka as hy
from levitron.runtime.bench import heyoka as bh

def make():
    x, v = hy.make_vars("x", "v")
    return [(x, v), (v, -hy.par[0] * x)]

r = bh.run(make, np.array([1.0, 0.0]), np.array([4.0]), np.ones(2), 3.0, 1e-10,
           {"min_runs": 1, "patience": 0, "max_runs": 1}, key=bh.cache_key(what="oscillator", tol=1e-10))
print(r["compile_cached"], r["x_final"][0].hex(), r["x_final"][1].hex(), r["steps"])
"""


def test_heyoka_compiles_are_cached_on_disk_and_a_kill_leaves_no_half_pickle(tmp_path):
    """runtime/bench/heyoka.py: the first run compiles and stores the integrator in
    $LEVITRON_CACHE/heyoka, the second loads it (make_sys is not called) and ends in the same state
    bit for bit; a process killed between writing and renaming leaves only a temporary, which the
    next process's sweep removes; a damaged pickle is compiled again."""
    pytest.importorskip("heyoka")
    import os
    import subprocess
    import sys
    env = {**os.environ, "LEVITRON_CACHE": str(tmp_path)}

    def once(extra_env=None):
        return subprocess.run([sys.executable, "-c", _OSCILLATOR_RUN], capture_output=True, text=True,
                              check=False, env={**env, **(extra_env or {})})

    folder = tmp_path / "heyoka"
    killed = once({"LEVITRON_FAULT": f"heyoka_cache.written:{tmp_path / 'marker'}"})
    assert killed.returncode == -9, killed.stderr
    left = list(folder.iterdir())
    assert len(left) == 1 and left[0].name.startswith(".") and left[0].suffix == ".tmp"
    os.utime(left[0], (0, 0))                   # older than the sweep's grace period; owner dead
    first = once()
    assert first.returncode == 0, first.stderr
    assert sorted(p.suffix for p in folder.iterdir()) == [".pickle"]      # swept, then stored
    second = once()
    assert second.returncode == 0, second.stderr
    c1, *state1 = first.stdout.split()
    c2, *state2 = second.stdout.split()
    assert (c1, c2) == ("False", "True") and state1 == state2
    (pickle_file,) = folder.iterdir()
    pickle_file.write_bytes(pickle_file.read_bytes()[:1000])               # damaged
    third = once()
    assert third.returncode == 0, third.stderr
    c3, *state3 = third.stdout.split()
    assert c3 == "False" and state3 == state1


def test_best_of_stops_when_the_minimum_is_stable():
    """runtime/bench/repeat.py: a constant time stops after min_runs + patience - 1 runs, a falling
    one runs until it levels off, and max_runs caps a noisy one."""
    from levitron.runtime.bench.repeat import best_of
    assert best_of(lambda: 1.0, min_runs=2, patience=2, budget_s=100).runs == 3
    falling = iter([8.0, 4.0, 2.0, 1.0, 1.0, 1.0, 1.0])
    t = best_of(lambda: next(falling), min_runs=2, patience=2, budget_s=100)
    assert (t.best, t.runs, t.stable) == (1.0, 6, True)
    noisy = iter([5.0, 4.0, 3.0, 2.0, 1.0, 0.5])
    t = best_of(lambda: next(noisy), min_runs=2, patience=2, max_runs=4, budget_s=100)
    assert (t.best, t.runs, t.stable) == (2.0, 4, False)


def test_startup_bench_times_commands_in_fresh_processes(tmp_path, monkeypatch):
    """runtime/bench/startup.py (quick, one command): the table and plot are written, each row has
    its budget and a positive time, and the scene is passed as its name."""
    import json

    from levitron.runtime.bench import startup
    from levitron.runtime.model.load import load_model
    monkeypatch.setattr(startup, "COMMANDS", (("--version", ["--version"], 0.2),
                                              ("info", ["info", "{scene}", "--json"], 5.0)))
    model = load_model(load_scene("thesis_stable"))
    res = startup.bench(model, tmp_path, quick=True)
    rows = {r["command"]: r for r in res["rows"]}
    assert rows["--version"]["min_s"] > 0 and rows["--version"]["budget_s"] == 0.2
    assert rows["info"]["argv"] == "levitron info thesis_stable --json"
    assert 2 <= rows["info"]["runs"] <= 3
    data = json.loads((tmp_path / "startup.json").read_text())
    assert data["rows"][0]["command"] == "--version" and len(data["load_average_1_5_15"]["before"]) == 3
    assert (tmp_path / "startup.csv").read_text().startswith("command,min_s,")
    assert (tmp_path / "startup.png").stat().st_size > 1000


def test_max_per_tenth_of_a_short_run():
    """The long run's per-tenth energy errors when the run ended early with fewer than ten samples
    (an expression plate's top that left its box): one part per sample, none for none."""
    from levitron.runtime.bench.work_precision import max_per_tenth
    assert max_per_tenth([1e-9, -3e-9, 2e-9]) == [1e-9, 3e-9, 2e-9]
    assert max_per_tenth([]) == []
    assert max_per_tenth([0.0] * 19 + [-5.0]) == [0.0] * 9 + [5.0]


def test_the_api_bench_runs_quick_and_measures_each_part(tmp_path):
    """runtime/bench/api.py in its quick mode: a row per part, the fastest call's wall time holds its
    own integration, and the report files exist (the 1 ms budget is measured by `make bench`)."""
    from pathlib import Path

    from levitron.runtime.bench import api
    from levitron.runtime.model.load import load_model
    res = api.bench(load_model(load_scene("thesis_stable")), tmp_path, quick=True)
    assert [r["part"] for r in res["rows"]] == ["full", "reduced"]
    for r in res["rows"]:
        assert 0 < r["integration_s"] < r["wall_s"] and r["overhead_s"] <= r["wall_s"] - r["integration_s"]
        assert r["calls"] >= 1 and r["budget_s"] == api.OVERHEAD_BUDGET_S
    assert all(Path(f).exists() for f in res["files"]) and "overhead" in res["headline"]


def test_the_per_call_race_keeps_the_loosest_tolerance_within_the_bound():
    """runtime/bench/per_call.py race_candidates: a contestant's loosest tolerances within the
    error bound are raced even when a slow stretch made their sweep rows look slow (square's taylor
    at 1e-8 was once left out for 10.8 us against 7.2 us at 1e-13), beside its fastest rows; rows
    outside the bound, of another method or not completed never are."""
    from levitron.runtime.bench.per_call import PER_CALL_BOUND, race_candidates

    def row(tol, err, wall, integrator="taylor", status="completed"):
        return {"backend": "c", "integrator": integrator, "tol": tol, "error": err, "wall_s": wall,
                "status": status}
    rows = [row(1e-6, 10 * PER_CALL_BOUND, 1e-6), row(1e-8, 0.25 * PER_CALL_BOUND, 10.8e-6),
            row(1e-9, 0.4 * PER_CALL_BOUND, 10.7e-6), row(1e-13, 1e-12, 7.2e-6),
            row(1e-14, 1e-13, 7.6e-6), row(1e-15, 1e-13, 8.9e-6), row(1e-16, 1e-13, 9.9e-6),
            row(1e-8, 0.1 * PER_CALL_BOUND, 1e-7, integrator="vern9"),
            row(1e-7, 0.1 * PER_CALL_BOUND, 1e-7, status="step_budget")]
    got = [r["tol"] for r in race_candidates(rows, "c", "taylor")]
    assert got == [1e-8, 1e-9, 1e-13, 1e-14, 1e-15]


@pytest.mark.parametrize("parts", [["reduced"], ["full", "reduced"]])
def test_the_api_benchs_legend_clears_its_axis_label(tmp_path, monkeypatch, parts):
    """runtime/bench/api.py draw: the legend under the axes overlapped the x label "wall time of the
    fastest call (ms)" on a scene with one part (a reduced-only scene's api.png, third audit): it
    was anchored at a fraction of the axes' height, which one bar makes short."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from levitron.runtime.bench import api
    from levitron.runtime.ui import plotting
    made = []
    save = plotting.save_figure
    monkeypatch.setattr(api, "save_figure", lambda fig, *a: made.append(fig) or save(fig, *a))   # keep it
    rows = [{"part": p, "integration_s": 2e-4, "wall_s": 5e-4, "budget_s": 1e-3} for p in parts]
    api.draw(rows, tmp_path / "api.png", "scene: Study.simulate")
    fig = made[0]
    r = FigureCanvasAgg(fig).get_renderer()
    ax = fig.axes[0]
    legend, label = ax.get_legend() or fig.legends[0], ax.xaxis.label
    lb, xb = legend.get_window_extent(r), label.get_window_extent(r)
    assert lb.y1 <= xb.y0 and lb.y0 >= fig.bbox.y0, (lb, xb)


def test_the_advice_bench_runs_in_its_quick_mode(tmp_path):
    """runtime/bench/advice.py: every case a person waits for (trim, the launch-odds designs, the
    yield design, the launch) runs as its command in a fresh process, with few launches, and the
    report has a row a case with its CPU time and exit 0."""
    from levitron.runtime.bench import advice
    from levitron.runtime.model.scenes import load_scene
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene("thesis_air", []))
    report = advice.bench(model, tmp_path, quick=True)
    cases = {row["case"]: row for row in report["rows"]}
    assert set(cases) == {"trim", "design-mass", "design-plate", "yield-plate", "launch"}
    assert all(row["exit"] == 0 and row["cpu_s"] > 0 for row in cases.values())
    assert (tmp_path / "advice.json").exists() and (tmp_path / "advice.png").exists()
