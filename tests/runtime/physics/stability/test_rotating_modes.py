"""The modes of a tilted magnet over a level axisymmetric base, in the frame turning with the spin
(runtime/physics/stability/rotating_modes.py): at moment tilt 0 they are the level top's (runtime/physics/
stability/modes.py) seen in that frame, |omega_s - sigma| for a transverse mode and the bounce unchanged,
and their lab frequencies are the level top's exactly; with the magnet tilted the frequencies are
the relative equilibrium's eigenvalues (RotatingTop.check); over a tilted base, or a plate without
axial symmetry with the magnet tilted, one line says that the modes are not given (the Floquet route)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus import rotating_equilibrium as req
from levitron.runtime.physics.stability import rotating_modes as rm
from levitron.runtime.physics.stability.modes import BOUNCE, Modes
from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis

SPIN = 1000.0


@pytest.fixture(scope="module")
def tilted(derived_model):
    return derived_model("thesis_stable", "top.moment_tilt=0.05")


def test_at_tilt_zero_they_are_the_level_tops_modes_in_the_turning_frame(tilted):
    aligned = tilted.with_params({"moment_tilt": 0.0})
    z = tilted_analysis(tilted, aligned).equilibrium["z_level"]
    level = Modes.of(tilted, SPIN, z, p=aligned, hessian="jacobian")
    got = rm.turning_modes(tilted, SPIN, aligned)
    assert [m.name for m in got.modes] == [m.name for m in level.modes]
    for a, b in zip(level.modes, got.modes):
        want = a.frequency if a.name == BOUNCE else abs(a.signed - SPIN)
        assert b.frequency == pytest.approx(want, rel=1e-8), (a.name, b.frequency, want)
        assert b.lab_frequency == pytest.approx(a.frequency, rel=1e-8) and b.lab_sense == a.sense
        assert b.purity == pytest.approx(1.0, abs=1e-9)


def test_with_the_magnet_tilted_they_are_the_relative_equilibriums_eigenvalues(tilted):
    got = rm.turning_modes(tilted, SPIN)
    aligned = tilted.with_params({"moment_tilt": 0.0})
    z = tilted_analysis(tilted, aligned).equilibrium["z_level"]
    ev = req.RotatingTop(tilted, tilted.p, z).check(SPIN).eigenvalues
    want = np.sort(ev.imag[ev.imag > 0])
    assert np.allclose(np.sort([m.frequency for m in got.modes]), want, rtol=1e-10)
    assert got.stable and got.moment_tilt == 0.05 and got.residual < 1e-10
    # the magnet's tilt moves the bounce (6.953 rad/s at 0.05 rad, 7.044 aligned) and keeps the names
    assert got[BOUNCE].lab_frequency == pytest.approx(6.953, abs=2e-3)
    assert [m.name for m in got.modes][-1] == "fast precession" and got["fast precession"].lab_sense == 1


def test_a_tilted_base_says_in_one_line_that_no_modes_are_given(tilted):
    p = tilted.with_params({"base_tilt": 1e-3})
    why = rm.refusal(tilted, p)
    assert why is not None and "\n" not in why and "Floquet route" in why and "base is tilted" in why
    with pytest.raises(UserError, match="Floquet route"):
        rm.turning_modes(tilted, SPIN, p)
    assert rm.refusal(tilted, tilted.p) is None
    assert rm.refusal(tilted, tilted.with_params({"moment_tilt": 0.0})) is None


def test_the_command_and_the_api_give_them(tilted, capsys):
    import levitron as lev
    assert cli.main(["stability", "thesis_stable", "--set", "top.moment_tilt=0.05", "--spin", "1000",
                     "--json"]) == 0
    md = json.loads(capsys.readouterr().out)["modes"]
    assert md["frame"] == "turning" and len(md["modes"]) == 5 and md["modes"][0]["lab_frequency"] > 0
    # both tilted (a periodic orbit): refused above, in one line; the base alone: test_tilted_modes.py
    got = lev.load("thesis_stable", overrides={"top.moment_tilt": 0.05}).modes(SPIN)
    assert isinstance(got, rm.TurningModes) and got.spin == SPIN
