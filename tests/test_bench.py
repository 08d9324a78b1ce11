"""`levitron bench SCENE --quick` runs the scene it is given (docs/contract.md `bench`): its own top, from
its own hover height, at the geometric mean of its stable spin interval; on every scene of scenes/,
and a clear one-line error exactly where the scene's top has no stable interval.
Speed is measured, not asserted: benchmarks are not timed tests."""
from __future__ import annotations

import csv
import json
import math

import pytest

from derive.scene import SCENES_DIR, load_scene
from runtime.physics import equilibrium as eqm
from runtime.bench.work_precision import ROW_KEYS
from runtime.physics.stability import stability_of

SCENES = [p.stem for p in sorted(SCENES_DIR.glob("*.toml"))]


@pytest.mark.parametrize("name", SCENES)
def test_bench_quick_on_every_scene(name, tmp_path, capsys):
    from runtime.cli.main import main
    from runtime.model.load import load_model
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
        assert (tmp_path / f"bench_{part}.png").stat().st_size > 5000
    goals = json.loads((tmp_path / "bench_goals.json").read_text())
    if "full" in model.parts:
        assert goals["full_rhs_ns"] > 0 and goals["full_rhs_ops"] > 0
        lr = goals["long_run"]
        assert lr["gauss4"]["status"] == lr["rk4"]["status"] == "completed"


def test_every_kind_of_scene_is_benched():
    """Not vacuous: most scenes have a stable interval and are benched, one is reduced-only."""
    from runtime.model.load import load_model
    ran = []
    for name in SCENES:
        model = load_model(load_scene(name))
        if "full" not in model.parts or stability_of(model).spin_interval is not None:
            ran.append(name)
    assert len(ran) >= 4 and "reduced_only" in ran


def test_bench_errors_shrink_with_tolerance():
    """A sanity check of the error measure on the quick rows: tighter tolerance or smaller step
    gives a smaller error for DOP853 and RK4 (the reference is not one of the rows)."""
    from runtime.bench.work_precision import bench_model
    from runtime.model.load import load_model
    res = bench_model(load_model(load_scene("thesis_stable")), "full", quick=True)
    by = {}
    for r in res["rows"]:
        by.setdefault(r["integrator"], []).append(r["error"])
    assert by["dop853"][1] < 1e-3 * by["dop853"][0]
    assert by["rk4"][1] < 1e-3 * by["rk4"][0]
    assert all(math.isfinite(e) for e in by["scipy-dop853"] + by["cvodes"])


def test_cheapest_by_bound_picks_the_fastest_run_within_each_bound():
    from runtime.bench.work_precision import BOUNDS, cheapest_by_bound
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
    from runtime.bench import work_precision as bench
    from runtime.model.load import load_model
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
    bench(model, scene_ref, overrides, out, quick) and scenes that exist."""
    import importlib
    import inspect

    from derive.scene import find_scene_file
    from runtime.bench.kinds import KINDS
    for kind in KINDS.values():
        fn = importlib.import_module(kind.module).bench
        assert list(inspect.signature(fn).parameters) == ["model", "scene_ref", "overrides", "out", "quick"]
        assert kind.scenes and all(find_scene_file(s) for s in kind.scenes)
