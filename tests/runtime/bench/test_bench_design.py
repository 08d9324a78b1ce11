"""The design bench (runtime/bench/design.py) in --quick mode: one verified design
optimisation over one key on thesis_stable, reported to JSON and CSV (no timing asserted)."""
from __future__ import annotations

import csv
import json
import subprocess
import sys

from levitron.scene.paths import ROOT


def test_quick_bench_writes_json_and_csv(tmp_path):
    res = subprocess.run([sys.executable, "-m", "levitron.runtime", "bench", "thesis_stable", "--kind", "design",
                          "--quick", "--out", str(tmp_path)], capture_output=True, text=True, cwd=ROOT,
                         check=False)
    assert res.returncode == 0, res.stderr
    data = json.loads((tmp_path / "bench_design.json").read_text())
    assert data["scene"] == "thesis_stable" and data["quick"] is True
    (case,) = data["cases"]
    assert case["case"] == "one_key" and case["objective"] == "spin-range" and not case["error"]
    assert case["solver_status"] in ("Solve_Succeeded", "Solved_To_Acceptable_Level")
    assert case["iterations"] > 0 and case["grid_points"] == 20 and case["wall_s"] > 0
    assert case["max_relative_gap"] <= 1e-8
    # the stiffness floor is the scene's own: a fifth of its top's stiffness (2.56 N/m), not a number
    from levitron.scene.load import load_scene
    from levitron.runtime.bench.design import STIFFNESS_FRACTION, stiffness_floor
    from levitron.runtime.model.load import load_model
    floor = stiffness_floor(load_model(load_scene("thesis_stable")))
    assert case["constraints"] == [floor] and floor == f"stiffness>={STIFFNESS_FRACTION * 2.5552696761:.4g}"
    rows = list(csv.DictReader((tmp_path / "bench_design.csv").open()))
    assert [r["case"] for r in rows] == ["one_key"]
    assert int(rows[0]["iterations"]) == case["iterations"]
    assert res.stdout.startswith("bench design: one_key ") and "bench_design.csv" in res.stdout
