"""The Python API as a scientist uses it: NumPy numbers, unknown names listed, no
string taken for a list, results with a useful repr, scipy-style success and message, a fit's
covariance and correlation, Study.scan's axes documented and validated."""
from __future__ import annotations

import numpy as np
import pytest

import levitron as lev


def test_a_numpy_loop_over_masses():
    """np.linspace yields np.float64: each is a number (it was refused as 'np.float64(0.0512)')."""
    z = []
    for m in np.linspace(0.0510, 0.0520, 3):
        st = lev.load("thesis_stable", {"top.mass": m}).stability()
        assert st.success and st.mass == pytest.approx(float(m), rel=1e-15)
        z.append(st.z_s)
    assert z[0] > z[1] > z[2]           # a heavier top hovers lower
    assert lev.load("thesis_stable", {"top.mass": np.float32(0.0512)}).value("top.mass") == \
        pytest.approx(0.0512, rel=1e-7)


def test_not_numbers_are_refused_in_one_line():
    with pytest.raises(lev.UserError, match=r"top.mass = \[0.05\] is not a number"):
        lev.load("thesis_stable", {"top.mass": [0.05]})


def test_unknown_quantity_lists_the_valid_ones(study):
    with pytest.raises(lev.UserError) as exc:
        study.gradient("spin_hi", ["top.mass"])
    msg = str(exc.value)
    assert "quantity 'spin_hi' is unknown: did you mean 'sigma_hi'? use one of" in msg
    assert "mass_window" in msg


def test_unknown_key_lists_the_scene_keys(study):
    with pytest.raises(lev.UserError,
                       match=r"scene key 'top.mas' is unknown: did you mean 'top.mass'\? use one of .*top\.mass"):
        study.value("top.mas")
    with pytest.raises(lev.UserError, match="plate.hole"):
        study.gradient("sigma_hi", ["top.mas"])


def test_a_string_where_a_list_is_expected_is_refused(study):
    """'top.mass' was taken letter by letter ("the scene has no number at t")."""
    with pytest.raises(lev.UserError, match=r"keys must be a list of names, not the string 'top.mass'"):
        study.gradient("sigma_hi", "top.mass")
    with pytest.raises(lev.UserError, match="constrain must be a list"):
        study.optimize("spin-range", {"top.mass": (0.0505, 0.0524)}, "stiffness>=0.5")


def test_simulate_takes_the_command_line_names(study):
    a = study.simulate(1000.0, tilt=0.02, tilt_azimuth=0.3, t_end=0.05)
    b = study.simulate(1000.0, tilt=0.02, azimuth=0.3, t_end=0.05)
    assert a.details["tilt_azimuth"] == 0.3 and a.final_state == b.final_state
    with pytest.raises(lev.UserError,
                       match=r"simulate option 'tend' is unknown: did you mean 't_end'\? use one of .*t_end"):
        study.simulate(1000.0, tend=0.05)


def test_scan_height_axis_is_a_fraction_and_validated(study):
    """The height axis is z0 = z_s (1 + h), |h| < 1/2 (documented); 0.6 is refused, an unknown
    axis lists the valid ones."""
    assert "FRACTION of the hover height" in lev.Study.scan.__doc__
    with pytest.raises(lev.UserError, match="fraction of z_s"):
        study.scan([1000.0], "height", [0.6], t_end=0.01)
    with pytest.raises(lev.UserError,
                       match=r"scan axis 'heigth' is unknown: did you mean 'height'\? use one of tilt, mass, height"):
        study.scan([1000.0], "heigth", [0.01], t_end=0.01)
    with pytest.raises(lev.UserError, match="not the string"):
        study.scan("1000", "tilt", [0.01], t_end=0.01)


def test_every_result_has_repr_success_and_message(study, tmp_path):
    results = {
        "equilibria": study.equilibria(),
        "stability": study.stability(),
        "simulation": study.simulate(1000.0, tilt=0.01, t_end=0.05),
        "scan": study.scan([1000.0, 5000.0], "tilt", [0.01], t_end=0.2),
        "design": study.optimize("spin-range", {"top.mass": (0.0505, 0.0524)}),
    }
    data = tmp_path / "h.csv"
    data.write_text(f"quantity,value,sigma\nz_s,{results['stability'].z_s!r},0.0001\n")
    results["fit"] = study.fit(str(data), {"top.mass": (0.0510, 0.0520)})
    for name, res in results.items():
        text = repr(res)
        assert text.startswith(type(res).__name__ + "(") and len(text) < 300, (name, text)
        assert "success=" in text and isinstance(res.success, bool)
        assert isinstance(res.message, str) and res.message, name
    assert results["stability"].success and "rad/s" in repr(results["stability"])
    n = int(results["scan"].levitating.sum())
    assert results["scan"].success and f"levitating at {50 * n:.3g}% of 2 points (spin x tilt, 200 ms each)" \
        in repr(results["scan"])
    design = results["design"]
    # no warning, but the optimum sits where sigma_lo switches branch: 0.1 g lighter halves the window
    # (runtime/design/sharpness.py), and the message (its plain view) and the JSON's status say so
    assert design.status_message.startswith(f"{design.solver_status}: spin-range 2386.99 rad/s; a knife edge: top.mass")
    assert design.message.startswith("optimum: top.mass = ") and "knife edge" in design.message
    assert lev.load("thesis").stability().success is False        # the 28.4 g top: no interval
    assert "no stable spin interval" in lev.load("thesis").stability().message


def test_a_fit_returns_covariance_and_correlation(study):
    """Two heights of two masses, two keys: the covariance is the stderr's square on its
    diagonal, the correlation has a unit diagonal and is symmetric."""
    from levitron.runtime.design.measurements import Row
    z1 = lev.load("thesis_stable", {"top.mass": 0.0512}).stability().z_s
    z2 = lev.load("thesis_stable", {"top.mass": 0.0518}).stability().z_s
    rows = [Row("z_s", z1, 1e-4, (("top.mass", 0.0512),)), Row("z_s", z2, 1e-4, (("top.mass", 0.0518),)),
            Row("sigma_hi", study.stability().spin_interval[1], 5.0)]
    fit = study.fit(rows, {"plate.murho": (-0.0028, -0.0024), "top.C": (1.1e-6, 1.5e-6)})
    cov, cor = fit.covariance, fit.correlation
    assert cov.shape == (2, 2) and np.allclose(cov, cov.T)
    for i, k in enumerate(fit.keys):
        assert np.sqrt(cov[i, i]) == pytest.approx(fit.parameters[k]["stderr"], rel=1e-12)
    assert np.allclose(np.diag(cor), 1) and abs(cor[0, 1]) <= 1
    d = fit.as_json()
    assert d["keys"] == ["plate.murho", "top.C"] and np.allclose(d["correlation"], cor)
