"""The start and the sides on the answer's fresh draws, paired with the answer
(runtime/design/paired_fresh.py): the start stops once the paired difference decides, and its
paired estimate holds the start's own Monte Carlo inside its interval; undecided, it is that Monte
Carlo exactly; where the answer is the start, the start's odds are the answer's, run once."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.runtime.design import launch_design as ld
from levitron.runtime.design.launch_design import maximize_launch_odds
from levitron.runtime.design.paired_fresh import decided, start_odds
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.scan import launch_odds as mc

KEYS = ["top.mass"]
ANSWER = 0.05192       # kg: thesis_air's trim (the band's upper part, 92 % of these launches)
# the first 200 fresh draws of the default hand, judged at 20 s (the full success time's ranking)
FRESH = mc.Request({}, n=200, seed=1, success_time=20.0, t_end=20.0, workers=1)


@pytest.fixture(scope="module")
def air(derived_model):
    model = derived_model("thesis_air")
    return model, ld.odds_at(model.ref, KEYS, [ANSWER], FRESH)


def test_mcnemars_test_decides_on_the_discordant_launches_only():
    yes, no = np.ones(100, bool), np.zeros(100, bool)
    assert not decided(yes, yes) and not decided(no, no)
    here = yes.copy()
    here[:4] = False               # 4 launches fall at the start only: |b - c| = 4 <= 3 sqrt(4)
    assert not decided(here, yes)
    here[:10] = False              # 10: 10 > 3 sqrt(10)
    assert decided(here, yes) and decided(yes, here)


def test_the_start_as_written_stops_once_the_paired_difference_decides(air):
    """51.5 g floats about 78 % of these launches against the answer's 92 %: half of the
    launches decides it, and the start's own Monte Carlo of all 200 lies inside the paired interval."""
    model, answer = air
    got = start_odds(model.ref, KEYS, [0.0515], answer, FRESH)
    full = ld.odds_at(model.ref, KEYS, [0.0515], FRESH)
    assert got["n"] == 100 and got["paired_with"] == "the answer's first 100 launches"
    lo, hi = got["probability_ci95"]
    assert lo <= full["probability"] <= hi
    assert not lo <= answer["probability"] <= hi        # the change is real, and the interval says so
    assert got["successes"] == sum(bool(v) for v in full["verdicts"][:100])


def test_an_undecided_start_runs_all_its_launches_and_gives_launchs_own_odds(air):
    """51.8 g floats these launches as often as the answer: nothing decides, so the start is its
    own Monte Carlo of all n, the odds `levitron launch` gives there."""
    model, answer = air
    got = start_odds(model.ref, KEYS, [0.0518], answer, FRESH)
    full = ld.odds_at(model.ref, KEYS, [0.0518], FRESH)
    assert "paired_with" not in got
    assert got == {k: full[k] for k in ("probability", "probability_ci95", "n", "seed", "successes")}


def test_a_start_that_cannot_hover_floats_never_and_says_why(air):
    model, answer = air
    got = start_odds(model.ref, KEYS, [0.07], answer, FRESH)
    assert got["probability"] == 0.0 and got["probability_ci95"] == [0.0, 0.0]
    assert "hover" in got["reason"]


def test_a_design_whose_answer_is_the_start_runs_it_once(derived_model, monkeypatch):
    """A steady hand at a spin every mass of the box holds: all points level, the answer the box's
    middle, which is the scene's own mass; the start's odds are the answer's, start_odds never runs."""
    from levitron.runtime.design import paired_fresh
    model = derived_model("thesis_stable")
    monkeypatch.setattr(paired_fresh, "start_odds", lambda *a, **k: pytest.fail("the start ran again"))
    steady = {"spin": "2000", "tilt": "0.002", "tilt_azimuth": "0", "offset": "0", "velocity": "0",
              "mass": "rel:0", "strength": "rel:0"}
    res = maximize_launch_odds(model, [Vary("top.mass", 0.0512, 0.0518)], mc.Request(steady, n=4, t_end=10.0))
    assert res.optimum["top.mass"] == pytest.approx(0.0515, rel=1e-12)
    assert res.start_launch_odds == res.launch_odds and res.probability == 1.0
