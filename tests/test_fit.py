"""Fitting scene keys to measurements (runtime/design/fit.py): a synthetic fit recovers the true values
within two reported standard errors; an unidentifiable fit is refused naming the keys."""
from __future__ import annotations

import numpy as np
import pytest

from derive.scene import load_scene
from runtime.design import fit
from runtime.errors import UserError
from runtime.model.load import load_model
from runtime.design.scene_keys import Vary, pvector, with_values
from runtime.physics.stability_casadi import CasadiStability


def _data(model, truth, plan, rng):
    cs = CasadiStability(model)
    rows = []
    for mass, quantities in plan:
        p = pvector(model.param_names, with_values(model.scene, {**truth, "top.mass": mass}))
        v = cs.values(p)
        for q in quantities:
            sigma = 1e-4 if q == "z_s" else 2.0
            rows.append(fit.Row(q, v[q] + sigma * rng.standard_normal(), sigma, (("top.mass", mass),)))
    return rows


def test_synthetic_fit_recovers_the_truth():
    """Heights at four masses and spin limits at two (thesis 3.3.2, 3.3.16), noisy (seed 0)."""
    model = load_model(load_scene("thesis_stable"))
    truth = {"plate.murho": -0.00263, "top.C": 1.30e-6}
    plan = [(0.0508, ["z_s"]), (0.0512, ["z_s", "sigma_lo", "sigma_hi"]),
            (0.0516, ["z_s", "sigma_lo", "sigma_hi"]), (0.052, ["z_s"])]
    rows = _data(model, truth, plan, np.random.default_rng(0))
    res = fit.fit(model, rows, [Vary.parse("plate.murho=-0.003:-0.0023"),
                                Vary.parse("top.C=1.1e-6:1.5e-6")])
    assert res.solver_status == "converged" and res.dof == len(rows) - 2
    for key, true in truth.items():
        got = res.parameters[key]
        assert got["stderr"] > 0
        assert abs(got["value"] - true) <= 2 * got["stderr"], (key, got, true)
    assert res.chi2 == pytest.approx(sum(r["normalized"] ** 2 for r in res.residuals))
    out = res.as_dict()
    assert set(out["parameters"]["top.C"]) >= {"value", "stderr"} and out["residuals"]


def test_heights_alone_cannot_separate_moment_and_strength():
    """Only mu x remanence enters m g + mu Phi_2 = 0 (thesis 3.3.2): refused, both keys named."""
    model = load_model(load_scene("square"))
    rows = _data(model, {}, [(0.0178, ["z_s"]), (0.018, ["z_s"]), (0.0182, ["z_s"])],
                 np.random.default_rng(1))
    with pytest.raises(UserError, match=r"top\.moment.*plate\.remanence|plate\.remanence.*top\.moment"):
        fit.fit(model, rows, [Vary.parse("top.moment=-0.2:-0.15"),
                              Vary.parse("plate.remanence=0.3:0.45")])


def test_rows_are_read_and_checked(tmp_path):
    f = tmp_path / "d.csv"
    f.write_text("quantity,value,sigma,overrides\n# a comment\nz_s,0.1,1e-4,top.mass=0.05\n")
    rows = fit.read_rows(f)
    assert rows == [fit.Row("z_s", 0.1, 1e-4, (("top.mass", 0.05),))]
    f.write_text("quantity,value,sigma\nheight,0.1,1e-4\n")
    with pytest.raises(UserError, match="line 2"):
        fit.read_rows(f)
    f.write_text("quantity,value,sigma\nz_s,0.1,0\n")
    with pytest.raises(UserError, match="sigma"):
        fit.read_rows(f)


def test_rows_that_share_their_overrides_share_their_work(monkeypatch):
    """Issue 17: 1000 rows took 117 s at 0.12 s a row. Rows at the same overrides (masses) now
    share the float routes' starts, values and Jacobians within one evaluation: 200 rows at 4
    masses start the routes 4 times an evaluation, not 200, and the fit is the 4-row fit's."""
    model = load_model(load_scene("thesis_stable"))
    truth = {"plate.murho": -0.00263}
    plan = [(0.0508, ["z_s"]), (0.0512, ["z_s"]), (0.0516, ["z_s"]), (0.052, ["z_s"])]
    rows = _data(model, truth, plan, np.random.default_rng(3))
    varies = [Vary.parse("plate.murho=-0.003:-0.0023")]
    calls = []
    real_starts = fit.sc.starts
    monkeypatch.setattr(fit.sc, "starts", lambda *a, **k: calls.append(1) or real_starts(*a, **k))
    prob = fit._Problem(model, rows * 50, varies)
    x = np.array([-0.0026])
    vals, r, J = prob.evaluate(x)
    assert len(calls) == 4 and vals.shape == (200,)
    few = fit._Problem(model, rows, varies).evaluate(x)
    np.testing.assert_array_equal(vals, np.tile(few[0], 50))
    np.testing.assert_array_equal(J, np.tile(few[2], (50, 1)))
