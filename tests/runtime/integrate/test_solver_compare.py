"""Thesis 3.1.3: Euler vs RK4 on the mass point held on a circle by F = -m v^2/r (eq. 3.1.8),
run in C over csrc/circle.c: error after each turn (figure 3.2) and steps before a 1 % energy
drift against the step (figure 3.3)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from levitron.runtime.bench.solver_compare import PERIOD, circle_system, error_per_turn, run, steps_to_energy_drift


@pytest.fixture(scope="module")
def circle():
    return circle_system()


def test_eq_3_1_8_figure_3_2_error_per_turn(circle):
    """Euler's error grows turn after turn; RK4's stays tiny (it grows only by the phase error,
    linearly in the number of turns)."""
    e = error_per_turn("euler", 100, 20, circle)
    r = error_per_turn("rk4", 100, 20, circle)
    assert np.all(np.diff(e) > 0) and e[-1] > 10 * e[0]
    assert r.max() < 1e-4 and r.max() < 25 * r[0]
    assert np.all(e > 1e3 * r)
    # the first turn: Euler's global error O(h) (eq. 3.1.7), RK4's O(h^4)
    e2 = error_per_turn("euler", 200, 1, circle)[0]
    r2 = error_per_turn("rk4", 200, 1, circle)[0]
    assert e[0] / e2 == pytest.approx(2.0, rel=0.1)
    assert r[0] / r2 == pytest.approx(16.0, rel=0.05)


def test_eq_3_1_3_figure_3_3_steps_before_one_percent_drift(circle):
    """Steps before the energy drifts by 1 %: Euler ~ h^-2 (energy grows by (1 + h^2 v^2/r^2)
    per step), RK4 ~ h^-6 (its energy error per step is O(h^6) on the circle): RK4 lasts far longer
    at every step size."""
    hs = np.array([0.004, 0.008, 0.016]) * PERIOD
    ne = np.array([steps_to_energy_drift("euler", h, 0.01, 10**6, circle)[0] for h in hs])
    hr = np.array([0.02, 0.03, 0.045]) * PERIOD
    nr = np.array([steps_to_energy_drift("rk4", h, 0.01, 10**7, circle) for h in hr])
    assert nr[:, 1].all()
    slope_e = np.polyfit(np.log(hs), np.log(ne), 1)[0]
    slope_r = np.polyfit(np.log(hr), np.log(nr[:, 0].astype(float)), 1)[0]
    assert slope_e == pytest.approx(-2.0, abs=0.1)
    assert slope_r == pytest.approx(-6.0, abs=0.3)
    assert steps_to_energy_drift("rk4", hs[-1], 0.01, 10**5, circle)[0] > 100 * ne[-1]


def test_solver_compare_writes_numbers_and_figures(tmp_path):
    res = run(tmp_path, quick=True)
    data = json.loads((tmp_path / "solver_compare.json").read_text())
    assert data["figure_3_2"]["error"]["euler"] == res["figure_3_2"]["error"]["euler"]
    for name in ("solver_compare_fig3_2.png", "solver_compare_fig3_3.png"):
        assert (tmp_path / name).stat().st_size > 5000
