"""Fitting scene keys to measurements (runtime/design/fit.py): a synthetic fit recovers the true values
within two reported standard errors; an unidentifiable fit is refused naming the keys."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.scene.load import load_scene
from levitron.runtime.design import fit, measurements
from levitron.runtime.errors import UserError
from levitron.runtime.model.load import load_model
from levitron.runtime.design.scene_keys import Vary, pvector, with_values
from levitron.runtime.physics.stability.differentiable import CasadiStability


def _data(model, truth, plan, rng):
    cs = CasadiStability(model)
    rows = []
    for mass, quantities in plan:
        p = pvector(model.param_names, with_values(model.scene, {**truth, "top.mass": mass}))
        v = cs.values(p)
        for q in quantities:
            sigma = 1e-4 if q == "z_s" else 2.0
            rows.append(measurements.Row(q, v[q] + sigma * rng.standard_normal(), sigma, (("top.mass", mass),)))
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
    out = res.as_json()
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
    rows = measurements.read_rows(f)
    assert rows == [measurements.Row("z_s", 0.1, 1e-4, (("top.mass", 0.05),))]
    f.write_text("quantity,value,sigma\nheight,0.1,1e-4\n")
    with pytest.raises(UserError, match="line 2"):
        measurements.read_rows(f)
    f.write_text("quantity,value,sigma\nz_s,0.1,0\n")
    with pytest.raises(UserError, match="sigma"):
        measurements.read_rows(f)


def test_rows_that_share_their_overrides_share_their_work(monkeypatch):
    """1000 rows once took 117 s at 0.12 s a row. Rows at the same overrides (masses) now
    share the float routes' starts, values and Jacobians within one evaluation: 200 rows at 4
    masses start the routes 4 times an evaluation, not 200, and the fit is the 4-row fit's."""
    model = load_model(load_scene("thesis_stable"))
    truth = {"plate.murho": -0.00263}
    plan = [(0.0508, ["z_s"]), (0.0512, ["z_s"]), (0.0516, ["z_s"]), (0.052, ["z_s"])]
    rows = _data(model, truth, plan, np.random.default_rng(3))
    varies = [Vary.parse("plate.murho=-0.003:-0.0023")]
    calls = []
    real_starts = fit.diffable.starts
    monkeypatch.setattr(fit.diffable, "starts", lambda *a, **k: calls.append(1) or real_starts(*a, **k))
    prob = fit._Problem(model, rows * 50, varies)
    x = np.array([-0.0026])
    vals, r, J = prob.evaluate(x)
    assert len(calls) == 4 and vals.shape == (200,)
    few = fit._Problem(model, rows, varies).evaluate(x)
    np.testing.assert_array_equal(vals, np.tile(few[0], 50))
    np.testing.assert_array_equal(J, np.tile(few[2], (50, 1)))


def _rows_at_masses(model, masses, seed):
    """z_s at most masses, a critical spin at every third (thesis_stable, plate.murho -0.00263)."""
    from levitron.runtime.physics.stability import differentiable as diffable
    cs, rng, rows = CasadiStability(model), np.random.default_rng(seed), []
    for i, m in enumerate(masses):
        p = pvector(model.param_names, with_values(model.scene, {"plate.murho": -0.00263,
                                                                 "top.mass": float(m)}))
        v = cs.values(p, diffable.starts(model, p))
        q = "z_s" if i % 3 else ("sigma_lo" if i % 2 else "sigma_hi")
        s = 1e-4 if q == "z_s" else 2.0
        rows.append(measurements.Row(q, v[q] + s * rng.standard_normal(), s, (("top.mass", float(m)),)))
    return rows


def test_warm_started_fit_gives_the_cold_fits_numbers(monkeypatch):
    """Rows at distinct masses (no shared sites) are batched through one mapped CasADi call, and
    after the first evaluation the rootfinders start from the last accepted roots, not from the
    float routes (a float-route survey per site at the start, at the optimum and where a warm
    root fails its checks; here a third of the cold path's at most). The fit
    is the one of the cold path (every evaluation from the float routes, as before batching): its
    values to 1e-12, its model values to the rootfinders' tolerance (15 rows at 15 masses, chi2 11.6
    with 13 degrees of freedom)."""
    model = load_model(load_scene("thesis_stable"))
    rows = _rows_at_masses(model, np.linspace(0.0506, 0.0522, 100)[:30:2], 0)
    varies = [Vary.parse("plate.murho=-0.003:-0.0023"), Vary.parse("top.C=1.1e-6:1.5e-6")]
    calls = []
    real_starts = fit.diffable.starts
    monkeypatch.setattr(fit.diffable, "starts", lambda *a, **k: calls.append(1) or real_starts(*a, **k))
    warm = fit.fit(model, rows, varies)
    n_warm = len(calls)
    calls.clear()
    monkeypatch.setattr(fit._Problem, "accept", lambda self: None)     # no warm starts: as before
    cold = fit.fit(model, rows, varies)
    assert len(calls) >= (cold.iterations + 1) * len(rows)
    assert n_warm <= len(calls) / 3, (n_warm, len(calls))
    for key in cold.parameters:
        for what in ("value", "stderr"):
            assert warm.parameters[key][what] == pytest.approx(cold.parameters[key][what],
                                                               rel=1e-12 if what == "value" else 1e-10)
    assert warm.chi2 == pytest.approx(cold.chi2, rel=1e-10)
    # the model values are roots the rootfinders stop at a residual of 1e-12 (NEWTON_STRICT): a root
    # is defined to about 1e-11 relative, and sigma_hi from the two paths' starts differs by 3e-11
    np.testing.assert_allclose([r["model"] for r in warm.residuals],
                               [r["model"] for r in cold.residuals], rtol=1e-10)


def test_a_warm_optimum_the_cold_routes_disagree_with_is_refitted_cold(monkeypatch):
    """If the cold evaluation at the warm optimum disagrees (here: made to), the fit is rerun
    with every evaluation cold, and its answer is the cold fit's."""
    model = load_model(load_scene("thesis_stable"))
    rows = _rows_at_masses(model, np.linspace(0.0508, 0.052, 4), 1)
    varies = [Vary.parse("plate.murho=-0.003:-0.0023")]
    real = fit._Problem.evaluate

    def skewed(self, x, cold=False):
        v, r, J = real(self, x, cold)
        return (v * (1 + 1e-6), r, J) if self.use_warm and not cold else (v, r, J)
    monkeypatch.setattr(fit._Problem, "evaluate", skewed)
    res = fit.fit(model, rows, varies)
    monkeypatch.setattr(fit._Problem, "evaluate", real)
    monkeypatch.setattr(fit._Problem, "accept", lambda self: None)
    cold = fit.fit(model, rows, varies)
    assert res.parameters["plate.murho"]["value"] == pytest.approx(
        cold.parameters["plate.murho"]["value"], rel=1e-12)
