"""No verdict without the physics to support it (runtime/scan/launch_inputs.py check_decay_horizon):
a default success time (tau / 2 in air) shorter than one period of the top's slowest motion decides
nothing, so the Monte Carlo is refused in one line instead of counting every launch a success."""
from __future__ import annotations

import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc


def test_a_default_success_time_shorter_than_the_slowest_period_is_refused(derived_model):
    model = derived_model("thesis_air", "top.spin_decay_time=0.01")       # tau / 2 = 5 ms, the slow period 3.6 s
    with pytest.raises(UserError, match="shorter than one period of the top's slowest motion") as err:
        mc.Request({}, n=4).run(model, quiet=True)
    assert err.value.param == "success_time" and err.value.value == pytest.approx(0.005)
    assert "\n" not in str(err.value)


def test_a_success_time_given_is_the_persons_question_and_runs(derived_model):
    model = derived_model("thesis_air", "top.spin_decay_time=0.01")
    got = mc.Request({}, n=4, success_time=1.0, workers=1).run(model, quiet=True)
    assert got["n"] == 4 and got["success_time"] == 1.0
