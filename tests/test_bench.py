"""`levitron bench --quick` runs and writes its table and plots (DESIGN.md `bench` row keys).
Speed is measured, not asserted: benchmarks are not timed tests."""
from __future__ import annotations

import csv
import json
import math

import pytest

from runtime.bench import ROW_KEYS


def test_bench_quick_writes_tables_and_plots(tmp_path, capsys):
    from runtime.cli import main
    rc = main(["bench", "thesis", "--quick", "--out", str(tmp_path), "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    rows = out["rows"]
    assert {r["model"] for r in rows} == {"reduced", "full"}
    assert {r["backend"] for r in rows} == {"c", "casadi", "scipy"}
    for r in rows:
        assert set(ROW_KEYS) <= set(r)
        assert r["wall_s"] > 0
    for name in ("reduced", "full"):
        with open(tmp_path / f"bench_{name}.csv") as fh:
            table = list(csv.DictReader(fh))
        assert list(table[0])[:len(ROW_KEYS)] == list(ROW_KEYS)
        assert len(table) == sum(r["model"] == name for r in rows)
        data = json.loads((tmp_path / f"bench_{name}.json").read_text())
        assert data["reference_check"] < 1e-9          # the reference is far tighter than the rows
        assert (tmp_path / f"bench_{name}.png").stat().st_size > 5000
    goals = json.loads((tmp_path / "bench_goals.json").read_text())
    assert goals["full_rhs_ns"] > 0 and goals["full_rhs_ops"] > 0
    lr = goals["long_run"]
    assert lr["gauss4"]["status"] == lr["rk4"]["status"] == "completed"


def test_bench_errors_shrink_with_tolerance(tmp_path):
    """A sanity check of the error measure on the quick rows: tighter tolerance or smaller step
    gives a smaller error for DOP853 and RK4 (the reference is not one of the rows)."""
    from derive.scene import load_scene
    from runtime.bench import bench_model
    from runtime.model import load_model
    res = bench_model(load_model(load_scene("thesis")), "full", quick=True)
    by = {}
    for r in res["rows"]:
        by.setdefault(r["integrator"], []).append(r["error"])
    assert by["dop853"][1] < 1e-3 * by["dop853"][0]
    assert by["rk4"][1] < 1e-3 * by["rk4"][0]
    assert all(math.isfinite(e) for e in by["scipy-dop853"] + by["cvodes"])
