"""runtime/scan/launch_window.py: a launch up at the success time whose spin has decayed below its
own lower critical spin has no verdict (as in simulate and the stability map), and a launch whose
spin is well inside its window keeps its verdict."""
import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc

STEADY = {"tilt": "uniform:0,0.002", "offset": "0", "velocity": "0", "mass": "rel:0", "strength": "1"}


def test_launches_whose_spin_decays_out_of_the_window_have_no_verdict(derived_model):
    """thesis_air with an 8 s spin decay time, launched at 1750 rad/s and judged at 10.8 s: the
    spin ends at 1750 exp(-10.8 / 8) = 454 rad/s, below the lower critical spin of 459.6 rad/s, so
    every launch still up is past its window; the odds count only the launches that fell (the
    default hand's tilts and offsets drop some of them)."""
    model = derived_model("thesis_air", "top.spin_decay_time=8")
    res = mc.monte_carlo(model, {"spin": "normal:1750,1"}, n=40, success_time=10.8, workers=1)
    past = res["past_window"]
    assert past["launches"] > 0 and "below the lower critical spin" in past["reason"]
    assert res["outcomes"]["past_window"] == past["launches"]
    assert res["no_verdict"] == past["launches"] and res["successes"] == 0
    assert res["n"] - res["no_verdict"] == res["outcomes"]["left_box"] > 0


def test_a_spin_inside_its_window_at_the_success_time_keeps_its_verdict(derived_model):
    """The same top judged at 5 s: 1750 exp(-5 / 8) = 937 rad/s, twice the lower critical spin."""
    model = derived_model("thesis_air", "top.spin_decay_time=8")
    res = mc.monte_carlo(model, {**STEADY, "spin": "normal:1750,1"}, n=12, success_time=5.0, workers=1)
    assert res["past_window"]["launches"] == 0 and res["no_verdict"] == 0 and res["successes"] > 0


def test_no_verdict_anywhere_is_refused_with_what_gives_one(derived_model):
    model = derived_model("thesis_air", "top.spin_decay_time=8")
    with pytest.raises(UserError, match="run longer"):
        mc.monte_carlo(model, {**STEADY, "tilt": "0.0005", "spin": "1750"}, n=3, success_time=10.8, workers=1)
