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
