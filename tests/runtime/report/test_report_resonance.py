"""The report's launch in air says, where its launches cross an explosive resonance, on which side
of it to launch (runtime/report/real_launch.py resonance_text; the page renders its markers)."""
from __future__ import annotations

import levitron as lev
from levitron.runtime.report.real_launch import resonance_text
from levitron.runtime.words import render


class Odds(dict):
    """The part of a LaunchOdds the text reads."""
    reason = None


def test_the_report_tells_a_hand_at_the_resonance_which_side():
    model = lev.load("levitron_toy").model
    text = render(resonance_text(model, Odds(inputs={"spin": "normal:212,3"}, success_time=1.0)), "cli")
    assert text.startswith("<p>At 0.02135 kg the hand&#x27;s spins cross the explosive resonance at 213.121 rad/s")
    assert "launch below it" in text and text.endswith(".</p>"), text
    assert resonance_text(model, Odds(inputs={"spin": "normal:150,5"}, success_time=1.0)) == ""
