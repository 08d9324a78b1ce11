"""The tilt each spin tolerates (runtime/scan/tilt_tolerance.py): the bisection finds a known
edge, and on levitron_toy the curve dips beside the explosive three-wave resonance at 213 rad/s."""
from __future__ import annotations

import json

import numpy as np
import pytest

import levitron as lev
from levitron.runtime.scan import tilt_tolerance as tt


def test_the_bisection_finds_a_known_edge(monkeypatch, derived_model):
    """A stand-in top that floats exactly below tilt 0.01 (1 + spin / 1000): the curve is that edge
    to the bisection's resolution; one that floats at every tilt gets TILT_HI, one at none 0."""
    edge = lambda w: 0.01 * (1 + np.asarray(w) / 1000)      # noqa: E731

    def fake(model, spin, tilt, t_end, p):
        spin, tilt = np.broadcast_arrays(np.asarray(spin, float), np.asarray(tilt, float))
        return {"levitating": tilt < np.where(spin > 2500, np.inf, np.where(spin < 600, 0.0, edge(spin))),
                "untested": np.zeros(spin.shape, bool)}
    monkeypatch.setattr("levitron.runtime.scan.batch.simulate_many", fake)
    model = derived_model("thesis_stable")
    got = tt.tilt_tolerance(model, (500.0, 2700.0), 0.1065, t_end=1.0, n=12)
    mid = (got.spins >= 600) & (got.spins <= 2500)
    resolution = (tt.TILT_HI / tt.TILT_LO) ** (1 / 2 ** tt.BISECTIONS)
    assert np.all(got.max_tilt[mid] <= edge(got.spins[mid]))
    assert np.all(got.max_tilt[mid] * resolution >= edge(got.spins[mid]))
    assert np.all(got.max_tilt[got.spins > 2500] == tt.TILT_HI) and np.all(got.max_tilt[got.spins < 600] == 0)


def test_the_toys_tolerance_dips_beside_its_explosive_resonance():
    """levitron_toy, the spin held, 10 s: 0.09 rad of launch tilt floats at 150-180 rad/s, a
    quarter of it at 216 rad/s, beside the explosive triad slow precession = bounce +
    translation(+1) at 213 rad/s (docs/resonances.md), which names the dip."""
    study = lev.load("levitron_toy")
    s = study.stability()
    res = [r.as_json() for r in s.resonances]
    got = tt.tilt_tolerance(study.model, (150.0, 218.2), s.z_s, res, t_end=10.0, n=3)
    assert got.max_tilt[2] < 0.4 * min(got.max_tilt[:2]) and got.max_tilt[0] > 0.05
    (dip,) = got.dips
    assert dip["spin"] == pytest.approx(216.0, rel=1e-3)
    assert dip["resonance"]["explosive"] and dip["resonance"]["spin"] == pytest.approx(213.1, rel=1e-3)
    assert "slow precession = vertical bounce + translation(+1)" in "\n".join(got.lines())


def test_the_command_gives_the_curve_and_its_plot(tmp_path, capsys):
    from levitron.runtime.cli.main import main
    out = tmp_path / "tt.png"
    assert main(["stability", "levitron_toy", "--tilt-tolerance", "--plot", str(out), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)["tilt_tolerance"]
    assert len(r["spins"]) == tt.N_SPINS and len(r["max_tilt"]) == tt.N_SPINS and out.stat().st_size > 10_000
    assert main(["stability", "levitron_toy", "--plot", str(out)]) == 2
    assert "--tilt-tolerance" in capsys.readouterr().err
