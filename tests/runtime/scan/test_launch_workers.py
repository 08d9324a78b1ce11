"""The default number of workers (runtime/scan/workers.py): every usable core, the same answer as
a serial run at the same seed."""
from __future__ import annotations

import pytest

from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan.runners import usable_cores
from levitron.runtime.scan.workers import MIN_TASKS, auto_workers


def test_the_default_is_every_core_for_many_launches_and_serial_for_a_few():
    assert auto_workers(MIN_TASKS) == usable_cores()
    assert auto_workers(MIN_TASKS - 1) == 1


@pytest.mark.skipif(usable_cores() < 2, reason="one usable core: the default is serial")
def test_the_parallel_default_gives_the_serial_answer_launch_for_launch(derived_model):
    model = derived_model("thesis_air")
    kw = {"n": MIN_TASKS, "seed": 7, "t_end": 1.0, "quiet": True}
    prep = mc.prepare(model, {}, MIN_TASKS, 7, None, 1.0)
    assert prep.workers == usable_cores() > 1
    default = mc.monte_carlo(model, {}, **kw)
    serial = mc.monte_carlo(model, {}, workers=1, **kw)
    assert default["verdicts"] == serial["verdicts"]
    assert default["flight_time"]["values"] == serial["flight_time"]["values"]
    assert default.probability == serial.probability
