"""The stability quantities as CasADi Functions (runtime/physics/stability/differentiable.py, thesis 3.3.2-3.3.16):
they agree with the exact float routes to 1e-10 and their exact (implicit-function) gradients with
central finite differences to 1e-6, on every scene of scenes/ that has the quantity."""
from __future__ import annotations

import pytest

from levitron.scene.paths import SCENES_DIR
from levitron.scene.load import load_scene
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.stability import differentiable as diffable
from levitron.runtime.model.load import load_model
from levitron.runtime.physics.stability.analysis import stability_of

SCENES = sorted(p.stem for p in SCENES_DIR.glob("*.toml"))


@pytest.fixture(scope="module", params=SCENES)
def built(request):
    model = load_model(load_scene(request.param))
    return model, diffable.CasadiStability(model), diffable.starts(model, band=True)


def test_values_agree_with_float_routes(built):
    """z_s, stiffness, z_c, max_mass (thesis 3.3.2-3.3.3) and sigma_lo, sigma_hi (3.3.13-3.3.16)."""
    model, cs, st = built
    v = cs.values(st=st)
    rep = eqm.equilibria_of(model)
    z_s = rep.stable[0].z
    assert v["z_s"] == pytest.approx(z_s, rel=1e-10)
    assert v["stiffness"] == pytest.approx(rep.stable[0].stiffness, rel=1e-10)
    assert v["z_c"] == pytest.approx(rep.z_c, rel=1e-10)
    assert v["max_mass"] == pytest.approx(rep.max_mass, rel=1e-10)
    if model.has_function("full_jac"):
        interval = stability_of(model).spin_interval
        if interval is None:
            assert "sigma_lo" not in v
        else:
            assert (v["sigma_lo"], v["sigma_hi"]) == pytest.approx(interval, rel=1e-10)


def test_band_agrees_with_float_band(built):
    """The stable band's edges (z_lo = z_c, z_hi: N(t) with a triple root, thesis 3.3.11) and masses
    against runtime/physics/equilibrium/bands.py's bisection (rtol 1e-12): 1e-10 relative (measured: < 5e-12)."""
    model, cs, st = built
    v = cs.values(st=st)
    band = eqm.equilibria_of(model, bands=True).stable_band
    assert band is not None and st.band is not None
    assert (v["z_lo"], v["z_hi"]) == pytest.approx(band.z, rel=1e-10)
    assert (v["m_lo"], v["m_hi"]) == pytest.approx(band.mass, rel=1e-10)
    assert v["mass_window"] == pytest.approx((band.mass[1] - band.mass[0]) / band.mass[1], rel=1e-8)


def test_gradients_match_central_differences(built):
    """Central differences of the rootfinders' values, step 1e-6 relative on each parameter; a
    component is compared against the size of its terms, |dy/dp_k| + |y / p_k| (the contract's
    rule near a zero of the quantity)."""
    model, cs, st = built
    v = cs.values(st=st)
    names = [k for k in ("z_s", "z_c", "sigma_lo", "sigma_hi", "z_hi", "m_lo", "mass_window")
             if k in v]
    assert {"z_s", "z_c", "z_hi", "mass_window"} <= set(names)
    for out in names:
        J = cs.jacobian(out, st=st)
        for k, pk in enumerate(model.p):
            if pk == 0:      # a friction rate of 0 (scenes in air): the ideal top's analysis
                assert J[k] == 0, (out, model.param_names[k], J[k])    # does not depend on it
                continue
            h = 1e-6 * abs(pk)
            up, dn = model.p.copy(), model.p.copy()
            up[k] += h
            dn[k] -= h
            fd = (cs.values(up, st)[out] - cs.values(dn, st)[out]) / (2 * h)
            size = abs(J[k]) + abs(v[out] / pk)
            assert abs(J[k] - fd) <= 1e-6 * size, (out, model.param_names[k], J[k], fd)
