"""runtime/bench/search_horizon.py in its quick mode: the study runs, writes its report, and its
odds fall with the horizon (a launch that floats to a time floats to every earlier one)."""
import json

from levitron.runtime.bench.search_horizon import HORIZONS, bench


def test_the_quick_study_writes_its_report_and_its_odds_fall_with_the_horizon(derived_model, tmp_path):
    res = bench(derived_model("thesis_air"), tmp_path, quick=True)
    summary = json.loads((tmp_path / "search_horizon.json").read_text())
    assert all((tmp_path / f).is_file() for f in ("search_horizon.csv", "search_horizon.png"))
    assert len(summary["rows"]) == 2 and 0 < summary["search_time"] <= summary["success_time"]
    for row in res["rows"]:
        odds = [row[f"odds_{h:g}"] for h in HORIZONS]
        assert all(a >= b for a, b in zip(odds, odds[1:]))
    assert "the search judges at" in res["headline"]
