"""No verdict without the physics to support it, on a map (runtime/scan/stability_map.py past_its_window):
a point in air that is up at t_end while its spin, by the decay law, has decayed below the lower critical
spin has not shown its fall yet; it is "past_window", no verdict, with simulate's own test
(runtime/integrate/verdict.py past_window), never "levitating"."""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.runtime.integrate.verdict import PAST_WINDOW, past_window
from levitron.runtime.scan import stability_map as sc
from levitron.runtime.scan.plot import PAST_WINDOW_COLOUR
from levitron.runtime.simulate.run import simulate

TAU = "top.spin_decay_time=8"     # s: over the default 10.8 s run 1750 rad/s decays to 454 < 460 rad/s, 2250 to 583


@pytest.fixture(scope="module")
def short_decay_map(derived_model):
    model = derived_model("thesis_air", TAU)
    return model, sc.scan(model, np.array([1750.0, 2250.0]), "tilt", np.array([0.01]), workers=1, quiet=True)


def test_a_point_whose_spin_left_the_window_before_t_end_is_no_verdict(short_decay_map):
    model, res = short_decay_map
    assert res.status == [[PAST_WINDOW], ["completed"]]
    assert res.levitating.tolist() == [[False], [True]]
    assert res.counts == {"levitating": 1, "fell": 0, "no_verdict": 1, "cannot_hover": 0}
    # the judgement is simulate's function, fed the decay law's spin at t_end
    lower = res.linear[0]["spin_interval"][0]
    spin_end = 1750.0 * math.exp(-res.t_end / 8.0)
    assert spin_end < lower < 2250.0 * math.exp(-res.t_end / 8.0)
    assert past_window("completed", res.t_end, lower, spin_end, 1.0) is not None


def test_simulate_says_no_verdict_at_the_same_point(short_decay_map):
    """The map and simulate agree: the same launch over the same run is no verdict in both."""
    model, res = short_decay_map
    sim = simulate(model, spin=1750.0, tilt=0.01, t_end=res.t_end)
    assert sim["levitating"] is None and sim["status"] == "completed"
    assert "below the lower critical spin" in sim["untested"]


def test_the_plain_view_json_and_picture_name_it(short_decay_map):
    model, res = short_decay_map
    d = res.as_json()
    assert d["past_window"]["points"] == 1 and "1750" in d["past_window"]["reason"]
    assert d["fraction_levitating"] == 0.5
    lines = res.lines(face="cli")
    assert "1 runs past the stable window at t_end, without a verdict" in lines[0]
    assert "no verdict: 1 of 2 runs past the stable window at t_end" in lines[1]
    assert "(1 of 1)" in lines[1]       # one verdict in the row: the point that stayed up
    assert any(line.startswith("no verdict past the stable window at t_end: spin 1750 rad/s") for line in lines)
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgba
    fig = plt.figure()
    ax = res.plot(ax=fig.add_subplot())
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(lab.startswith("no verdict: up at t_end") for lab in labels)
    colours = {tuple(np.round(m.get_cmap()(0), 3)) for m in ax.collections if hasattr(m, "get_cmap")}
    plt.close(fig)
    assert tuple(np.round(to_rgba(PAST_WINDOW_COLOUR), 3)) in colours


def test_a_decay_time_far_below_a_spin_period_gives_no_verdict(derived_model):
    """The issue's case on a map: tau = 0.2 us, a 20 ms run; the spin is gone long before the end."""
    model = derived_model("thesis_air", "top.spin_decay_time=2e-7")
    res = sc.scan(model, np.array([2500.0]), "tilt", np.array([0.01]), t_end=0.02, workers=1, quiet=True)
    assert res.status == [[PAST_WINDOW]] and not res.levitating.any()
    assert "levitating at 0% of 1 points" in res.lines()[0]


def test_without_air_no_point_is_past_its_window(model):
    res = sc.scan(model, np.array([300.0, 1500.0]), "tilt", np.array([0.01]), t_end=0.5, workers=1, quiet=True)
    assert res.as_json()["past_window"] == {"points": 0, "reason": None}
    assert PAST_WINDOW not in [s for row in res.status for s in row]
