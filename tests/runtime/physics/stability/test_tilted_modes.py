"""The linear modes over a tilted base, the magnet aligned (runtime/physics/stability/tilted_modes.py): the level
top's as the tilt goes to 0, and stable exactly inside the tilted spin interval of the eigenvalue
route (runtime/physics/apparatus/tilted_stability.py), which reads the same Jacobian by another path."""
from __future__ import annotations

import json

import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.errors import UserError
from levitron.runtime.physics.stability.modes import Modes
from levitron.runtime.physics.stability.tilted_modes import tilted_base_modes
from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis

SPIN = 1000.0


def _key(md):
    return [(m.name, m.sense, m.krein) for m in md.modes]


def test_a_vanishing_tilt_gives_the_level_tops_modes(derived_model):
    level = Modes.at(derived_model("thesis_stable"), SPIN)
    tiny = tilted_base_modes(derived_model("thesis_stable", "plate.tilt=1e-9"), SPIN)
    assert _key(tiny) == _key(level)
    for a, b in zip(tiny.modes, level.modes):
        assert a.frequency == pytest.approx(b.frequency, rel=1e-6)


def test_the_modes_are_stable_exactly_inside_the_tilted_spin_interval(derived_model):
    """At 1 mrad the bounce (7.04 -> 7.17 rad/s) and the translations move; the modes stay on the
    imaginary axis inside the eigenvalue route's interval, and a pair leaves it just outside."""
    model = derived_model("thesis_stable", "plate.tilt=0.001")
    lo, hi = tilted_analysis(model, model.p).spin_interval
    inside = tilted_base_modes(model, (lo * hi) ** 0.5)
    assert inside.stable and inside.window == (lo, hi)
    assert not tilted_base_modes(model, 0.98 * lo).stable
    assert tilted_base_modes(model, 1.02 * lo).stable
    at = tilted_base_modes(model, SPIN)
    assert at["vertical bounce"].frequency == pytest.approx(7.173, rel=1e-3)
    assert at["slow precession"].krein == -1 and at["fast precession"].sense == 1


def test_the_command_and_the_api_give_them_and_refuse_a_level_base(derived_model, capsys):
    import levitron as lev
    assert cli.main(["stability", "thesis_stable", "--set", "plate.tilt=0.001", "--spin", "1000", "--json"]) == 0
    md = json.loads(capsys.readouterr().out)["modes"]
    assert [m["name"] for m in md["modes"]][0] == "vertical bounce" and md["stable"]
    got = lev.load("thesis_stable", overrides={"plate.tilt": 0.001}).modes(SPIN)
    assert isinstance(got, Modes) and got.spin == SPIN
    with pytest.raises(UserError, match="tilted base with the magnet aligned"):
        tilted_base_modes(derived_model("thesis_stable"), SPIN)
