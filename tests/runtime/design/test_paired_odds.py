"""The paired comparison of a design's points (runtime/design/paired_odds.py): the stopping rule,
no duplicate evaluations, and the same advice with and without early stopping."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.runtime.design.launch_design import EDGE_STEPS, GRID, maximize_launch_odds
from levitron.runtime.design.paired_odds import MIN_DISCORDANT, PairedOdds
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.scan import launch_odds as mc

# a steady hand at 2000 rad/s: the odds are 1 over the masses whose linear interval holds the spin
# and 0 elsewhere (test_launch_design.py's known answer), with a small tilt spread so launches differ
STEADY = {"spin": "2000.0", "tilt": "uniform:0.001,0.003", "tilt_azimuth": "0", "offset": "0",
          "velocity": "0", "mass": "rel:0", "strength": "rel:0"}


def _odds(best: np.ndarray) -> PairedOdds:
    odds = PairedOdds(None, ["top.mass"], mc.Request({}, n=len(best)), [(0.0, 1.0)])
    odds.best, odds.best_k = best, int(best.sum())
    return odds


def test_a_point_clearly_worse_launch_by_launch_is_stopped_and_a_close_one_is_not():
    """McNemar's rule on the discordant launches: 12 launches the incumbent floats and the point
    does not, none the other way, decide (12 > 3 sqrt(12)); 3 against 1 do not."""
    n = 400
    best = np.zeros(n, bool)
    best[:200] = True
    worse = best.copy()
    worse[:12] = False
    assert _odds(best)._worse(worse, 100, n)
    close = best.copy()
    close[:3] = False
    close[250] = True
    assert not _odds(best)._worse(close, 300, n)
    # below MIN_DISCORDANT nothing is decided by the test, however lopsided
    few = best.copy()
    few[:MIN_DISCORDANT - 1] = False
    assert not _odds(best)._worse(few, 100, n)


def test_a_point_that_cannot_reach_the_incumbent_is_stopped_whatever_the_test_says():
    n = 20
    best = np.ones(n, bool)             # the incumbent floats every launch
    one_fall = np.ones(n, bool)
    one_fall[0] = False
    assert _odds(best)._worse(one_fall, 5, n)


def test_a_stopped_point_is_estimated_below_the_incumbent():
    n = 400
    best = np.zeros(n, bool)
    best[:300] = True
    worse = best.copy()
    worse[:40] = False
    got = _odds(best)._stopped(worse, 100, n)
    assert got["stopped_early"] and got["launches_run"] == 100
    assert got["probability"] == pytest.approx(0.75 - 0.40) and got["probability"] < 0.75


def test_two_points_a_float_step_apart_are_evaluated_once(monkeypatch):
    odds = PairedOdds(None, ["top.mass"], mc.Request({}, n=4), [(0.05, 0.052)])
    calls = []
    monkeypatch.setattr(odds, "_run", lambda x, k: calls.append(x) or {"probability": 0.5})
    a = 0.051
    assert odds((a,)) == odds((np.nextafter(a, 1.0),)) == {"probability": 0.5}
    assert len(calls) == 1 and odds.counts["duplicates"] == 1
    odds((0.0515,))
    assert len(calls) == 2


def test_early_stopping_gives_the_advice_of_the_full_search_with_fewer_launches(derived_model):
    """The steady hand's known answer (the middle of the masses that hold the spin): the search with
    paired stopping advises the same mass, with the same odds on fresh draws, as the search that
    runs every launch of every point, and runs fewer launches."""
    model = derived_model("thesis_stable")
    box = [Vary("top.mass", 0.0504, 0.0530)]
    request = mc.Request(STEADY, n=16, t_end=3.0, workers=1)
    early = maximize_launch_odds(model, box, request)
    full = maximize_launch_odds(model, box, request, early=False)
    assert early.optimum == full.optimum and early.launch_odds == full.launch_odds
    assert early.probability == 1.0
    assert full.work["stopped_early"] == 0 and early.work["stopped_early"] > 0
    assert early.work["launches_run"] < full.work["launches_run"] <= full.work["launches_full"]


def test_the_search_at_its_search_time_gives_the_advice_of_the_search_at_the_success_time(derived_model):
    """A steady hand in air (thesis_air, spin 1100 rad/s, small tilts): the launches float over the
    masses its band holds and fall fast outside, the known answer being the band's middle. A
    search that judges its launches at its search time (an eighth of the success time, at least
    three slow periods) advises the same mass, with
    the same odds on fresh draws, as one that judges them at the success time; the answer is
    judged at the success time in both."""
    model = derived_model("thesis_air")
    box = [Vary("top.mass", 0.0500, 0.0526)]
    request = mc.Request({**STEADY, "spin": "1100.0"}, n=16, success_time=40.0, workers=1)
    short = maximize_launch_odds(model, box, request)
    full = maximize_launch_odds(model, box, request, horizon=False)
    # the same mass to the resolution of the plateau's edges: a grid cell halved EDGE_STEPS times
    # (near a band edge the top falls slowly, so the short horizon may place an edge one step out)
    step = (box[0].hi - box[0].lo) / (GRID[1] - 1) / 2 ** EDGE_STEPS
    assert abs(short.optimum["top.mass"] - full.optimum["top.mass"]) <= step
    assert short.launch_odds == full.launch_odds and short.probability == 1.0


def test_a_point_is_level_with_the_incumbent_unless_the_paired_test_says_it_is_worse():
    """Level: the incumbent floats in fewer than MIN_DISCORDANT, or at most Z_LEVEL sqrt(b + c), more
    of their paired launches; a point not run through (stopped, never run) is not level."""
    best = np.zeros(400, bool)
    best[:300] = True
    odds = _odds(best)
    near, far = best.copy(), best.copy()
    near[:3] = False                        # 3 launches worse: level whatever the noise
    far[:40] = False                        # 40 worse, none better: 40 > 2 sqrt(40)
    odds.verdicts[odds.key((0.2,))], odds.verdicts[odds.key((0.8,))] = near, far
    swap = best.copy()
    swap[:30], swap[300:330] = False, True  # 30 each way: no difference at all
    odds.verdicts[odds.key((0.5,))] = swap
    assert odds.level((0.2,)) and odds.level((0.5,)) and not odds.level((0.8,))
    assert not odds.level((0.9,))
