"""What a design says beside its optimum (runtime/design/design_notes.py): a mass-window whose band
no longer holds the scene's top, keys that barely move the objective."""
from __future__ import annotations

import json

from levitron.runtime.cli.main import main
from levitron.runtime.design.design_notes import BARELY, barely_moves_note, mass_window_note


def test_the_notes_on_numbers():
    assert mass_window_note((0.0169, 0.0177), 0.0182).startswith("at the optimum the stable band holds")
    assert mass_window_note((0.0169, 0.0185), 0.0182) is None and mass_window_note(None, 0.0182) is None
    assert "barely move" in barely_moves_note("mass-window", 0.0403, 0.0403 * (1 - BARELY / 2))
    assert barely_moves_note("mass-window", 0.05, 0.04) is None and barely_moves_note("x", 1.0, None) is None


def test_a_mass_window_over_the_remanence_says_both(capsys):
    """ring_magnet: over the remanence the band's relative width moves by a twentieth of a percent,
    and at the optimum it holds 17-17.7 g, not the scene's 18.2 g top: both said in the warnings."""
    assert main(["optimize", "ring_magnet", "--maximize", "mass-window", "--vary", "plate.remanence=0.37:0.41",
                 "--json"]) == 0
    w = json.loads(capsys.readouterr().out)["warnings"]
    assert any("not the scene's top" in x for x in w) and any("barely move" in x for x in w)


def _launch_design(odds: list[float], ci=(0.5, 0.9), stopped=(), per_point=100, n=100):
    from levitron.runtime.design.launch_design_answer import LaunchDesign
    rows = [{"plate.remanence": 0.1 + i, "probability": p, **({"stopped_early": True} if i in stopped else {})}
            for i, p in enumerate(odds)]
    answer = {"probability": 0.7, "probability_ci95": list(ci), "n": n, "seed": 1, "successes": 70}
    return LaunchDesign({"plate.remanence": 0.1}, {"plate.remanence": 0.1}, answer, answer, max(odds), rows,
                        {}, 1.0, 1.0, 0, n, 0.0, [], work={"launches_per_point": per_point})


def test_the_noise_note_on_numbers():
    """below_noise_note: the search points' odds span less than the answer's Wilson half-width, or
    every point ran all its launches and differs from the best in fewer than MIN_DISCORDANT."""
    from levitron.runtime.design.design_notes import below_noise_note
    from levitron.runtime.design.paired_odds import MIN_DISCORDANT
    said = below_noise_note(_launch_design([0.70, 0.72, 0.61]))         # spread 0.11 < half-width 0.2
    assert said == ("the key plate.remanence moves the odds less than their noise (100 launches): any value "
                    "in the box does as well")
    assert below_noise_note(_launch_design([0.70, 0.30])) is None        # 0.4 > 0.2
    level = [0.70, 0.70 - (MIN_DISCORDANT - 1) / 1000]                   # 3 launches of 1000 apart
    assert below_noise_note(_launch_design(level, ci=(0.699, 0.701), per_point=1000)) is not None
    assert below_noise_note(_launch_design(level, ci=(0.699, 0.701), per_point=1000, stopped=(1,))) is None
    apart = [0.70, 0.70 - MIN_DISCORDANT / 1000]
    assert below_noise_note(_launch_design(apart, ci=(0.699, 0.701), per_point=1000)) is None


def test_a_launch_design_over_a_key_that_cannot_matter_says_so(capsys):
    """levitron_toy over its remanence within +-0.01 %: every point floats the same launches, so
    the design says that any value in the box does as well (and still gives its answer)."""
    r0 = 0.1568515
    assert main(["optimize", "levitron_toy", "--maximize", "launch-odds", "--vary",
                 f"plate.remanence={r0 * (1 - 1e-4):.9g}:{r0 * (1 + 1e-4):.9g}", "--n", "8", "--t-end", "1",
                 "--workers", "1", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    said = [w for w in r["warnings"] if "less than their noise" in w]
    assert said == ["the key plate.remanence moves the odds less than their noise (8 launches): any value in "
                    "the box does as well"], r["warnings"]
