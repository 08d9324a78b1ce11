"""A Trim answer built from numbers, for the tests of its words and of its "no change" rule
(runtime/design/trim_answer.py)."""
from __future__ import annotations


def trim_with(start_ci, p, paired: bool = False):
    """A trim whose best mass floats `p`, the mass as written within `start_ci` (95 %); paired: the
    mass as written stopped on 250 paired launches, McNemar's test having decided the difference
    (runtime/design/paired_fresh.py start_odds)."""
    from levitron.runtime.design.launch_design_answer import LaunchDesign
    from levitron.runtime.design.trim_answer import Trim
    odds = {"probability": p, "probability_ci95": [p - 0.03, p + 0.03], "n": 1000, "seed": 1,
            "successes": int(1000 * p)}
    start = {"probability": sum(start_ci) / 2, "probability_ci95": list(start_ci), "n": 1000, "seed": 1,
             "successes": int(500 * sum(start_ci))}
    if paired:
        start.update(n=250, successes=int(125 * sum(start_ci)), paired_with="the answer's first 250 launches")
    design = LaunchDesign({"top.mass": 0.05102}, {"top.mass": 0.0510}, odds, start, p, [], {}, 75.0, 75.0, 0,
                          1000, 1.0)
    widest = {"mass": 0.0504, "z_s": 0.1, "spin_interval": None, "launch_odds": start}
    return Trim(0.0510, (0.0503, 0.0525), design, [], widest)
