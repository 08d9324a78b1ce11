"""Vertical equilibria, z_c, the largest mass and the stable band (thesis 3.3.1-3.3.3; docs/contract.md).

The plate here is the thesis's thin annulus in closed form (numpy), independent of the generated
model; one test compares it with the generated model when that is available.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.runtime.physics.equilibrium import bands

from levitron.runtime.physics.routes import ray_algebra
from levitron.runtime.physics.equilibrium import finder as eqm

from tests.helpers.annulus import A_PLATE, A_TOP, C_TOP, M_TOP, W_PLATE, G, dq, annulus, fitted_murho


def test_closed_form_derivatives():
    """The hand-written Phi_k are the derivatives of Phi_0 (central differences, relative 1e-6)."""
    on = annulus(A_PLATE, W_PLATE)
    for z in (0.01, 0.05, 0.0762, 0.12, 0.3):
        h = 1e-5 * z
        for k in range(4):
            fd = (on(z + h)[k] - on(z - h)[k]) / (2 * h)
            assert abs(fd - on(z)[k + 1]) <= 1e-6 * max(abs(on(z)[k + 1]), abs(on(z)[k]) / z)


def test_eq_3_3_2_thesis_second_equilibrium():
    """Fit mu*rho to the thesis's lower equilibrium (7.62 cm); the tool predicts the upper one.

    Measured: 15.739 cm against the thesis's 15.68 cm, +0.38 %. The rounding of the input 7.62 cm
    (+-0.005 cm) alone moves the prediction over [15.706, 15.773] cm (+0.16 % .. +0.59 %), so the
    honest tolerance is 0.6 %: the thesis's 15.68 lies 0.16 % below even that range (presumably its
    own root-finding or plot reading)."""
    mu = fitted_murho()
    eqs = eqm.vertical_equilibria(annulus(A_PLATE, W_PLATE), M_TOP, G, mu, A_PLATE)
    assert len(eqs) == 2
    lo, hi = eqs
    assert abs(lo.z - 0.0762) <= 1e-12 * 0.0762 and not lo.vertically_stable
    assert hi.vertically_stable
    assert abs(hi.z - 0.1568) / 0.1568 <= 0.006
    spread = [eqm.vertical_equilibria(annulus(A_PLATE, W_PLATE), M_TOP, G, fitted_murho(z1), A_PLATE)[1].z
              for z1 in (0.07615, 0.07625)]
    assert max(abs(z - 0.1568) / 0.1568 for z in spread) <= 0.006
    assert min(spread) < hi.z < max(spread)


def test_eq_3_3_3_vertical_stability_is_the_sign_of_mu_phi3():
    """Each equilibrium's flag is the sign of U'' = mu Phi_3 (3.3.3), checked against a finite
    difference of U' = m g + mu Phi_2."""
    mu = fitted_murho()
    on = annulus(A_PLATE, W_PLATE)
    for e in eqm.vertical_equilibria(on, M_TOP, G, mu, A_PLATE):
        h = 1e-6 * e.z
        d = (M_TOP * G + mu * on(e.z + h)[2] - (M_TOP * G + mu * on(e.z - h)[2])) / (2 * h)
        assert (d > 0) == e.vertically_stable
        assert abs(d - e.stiffness) <= 1e-5 * abs(e.stiffness)


def test_z_c_and_max_mass():
    """Phi_3(z_c) = 0 (relative to the size of the terms of Phi_3) and m(z_c) is the largest hover
    mass on a dense grid."""
    mu = fitted_murho()
    on = annulus(A_PLATE, W_PLATE)
    z_c, m_max = eqm.critical_height(on, G, mu, A_PLATE)
    terms = 2 * math.pi * (abs(dq(4, z_c, W_PLATE)) + abs(dq(4, z_c, A_PLATE)))
    assert abs(on(z_c)[3]) <= 1e-13 * terms
    grid = np.linspace(0.01, 0.5, 20001)
    dense = max(-mu * on(z)[2] / G for z in grid)
    assert m_max >= dense * (1 - 1e-12)
    assert m_max <= dense * (1 + 1e-6)   # grid spacing 2.5e-5 m: m(z) is flat to ~1e-7 there


def test_too_heavy_has_no_equilibrium():
    """A top heavier than max_mass has no equilibrium (and none is invented)."""
    mu = fitted_murho()
    on = annulus(A_PLATE, W_PLATE)
    _, m_max = eqm.critical_height(on, G, mu, A_PLATE)
    assert eqm.vertical_equilibria(on, 1.001 * m_max, G, mu, A_PLATE) == []
    assert len(eqm.vertical_equilibria(on, 0.999 * m_max, G, mu, A_PLATE)) == 2


def test_dimensionless_scene_scales():
    """No fixed lengths: the same plate in units of its radius (g = 1, m = 1) gives z/a exactly."""
    mu_si = fitted_murho()
    on_si = annulus(A_PLATE, W_PLATE)
    z_si = [e.z for e in eqm.vertical_equilibria(on_si, M_TOP, G, mu_si, A_PLATE)]
    on_1 = annulus(1.0, W_PLATE / A_PLATE)
    mu_1 = -1.0 * 1.0 / on_1(0.0762 / A_PLATE)[2]
    z_1 = [e.z for e in eqm.vertical_equilibria(on_1, 1.0, 1.0, mu_1, 1.0)]
    assert np.allclose(np.array(z_1), np.array(z_si) / A_PLATE, rtol=1e-12, atol=0)
    zc_si, _ = eqm.critical_height(on_si, G, mu_si, A_PLATE)
    zc_1, _ = eqm.critical_height(on_1, 1.0, mu_1, 1.0)
    assert abs(zc_1 - zc_si / A_PLATE) <= 1e-12


@pytest.fixture(scope="module")
def thesis_report():
    return eqm.analyse(annulus(A_PLATE, W_PLATE), M_TOP, G, A_TOP, C_TOP, fitted_murho(), A_PLATE)


def test_stable_band_edges(thesis_report):
    """The band's edges are where the exact predicate flips: just inside a spin stabilises the top
    of mass m(z), just outside none does; the lower edge is z_c (there g31 = 0 and g21 < 1/sqrt 12,
    thesis 3.3.15), the upper one where two critical spins merge. The mass range is m(z) at the
    edges (m decreases on a vertically stable stretch)."""
    on = annulus(A_PLATE, W_PLATE)
    mu = fitted_murho()
    band = thesis_report.stable_band
    assert band is not None and len(thesis_report.stable_bands) == 1
    lo, hi = band.z
    assert abs(lo - thesis_report.z_c) <= 1e-10 * lo
    ok = lambda z: bands.spin_stabilisable(on(z), G, A_TOP, C_TOP, mu)
    assert ok(lo * (1 + 1e-6)) and ok(hi * (1 - 1e-6)) and ok(0.5 * (lo + hi))
    assert not ok(lo * (1 - 1e-6)) and not ok(hi * (1 + 1e-6))
    # near the upper edge the two critical spins are about to merge
    ph = on(hi * (1 - 1e-9))
    m_hi = -mu * ph[2] / G
    c = ray_algebra.RayCoefficients.from_physics(ph[1], ph[2], ph[3], m_hi, A_TOP, C_TOP, mu)
    (s_lo, s_hi), = ray_algebra.spin_intervals_discriminant(c)
    assert (s_hi - s_lo) / s_hi < 1e-3
    masses = sorted([-mu * on(lo)[2] / G, -mu * on(hi)[2] / G])
    assert np.allclose(band.mass, masses, rtol=1e-12, atol=0)


def test_thesis_top_hovers_outside_the_band(thesis_report):
    """The thesis's 28.4 g top hovers at 15.74 cm: vertically stable, but far above the stable band
    (~9.95-11.0 cm, masses ~50-52.5 g), so no spin rate stabilises it."""
    z_s = [e.z for e in thesis_report.equilibria if e.vertically_stable][0]
    assert z_s > thesis_report.stable_band.z[1] * 1.3
    assert not (thesis_report.stable_band.mass[0] <= M_TOP <= thesis_report.stable_band.mass[1])


def test_adiabatic_band_edges(thesis_report):
    """Berry-Simon band: from z_c (Phi_3 = 0) to where Phi_2^2 = 2 Phi_1 Phi_3 (relative to the size
    of those terms); it is reported beside the exact band, which here reaches higher."""
    on = annulus(A_PLATE, W_PLATE)
    band = thesis_report.adiabatic_band
    lo, hi = band.z
    assert abs(lo - thesis_report.z_c) <= 1e-10 * lo
    _, p1, p2, p3, _ = on(hi)
    assert abs(p2 * p2 - 2 * p1 * p3) <= 1e-9 * (p2 * p2 + abs(2 * p1 * p3))
    assert hi < thesis_report.stable_band.z[1]


def test_generated_model_onaxis_matches_closed_form():
    """The generated model's onaxis (thesis scene) equals the closed form (relative 1e-12)."""
    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene("thesis"))
    P = model.pvals()
    on = annulus(P["plate_a"], P["plate_w"], P["plate_rho"])
    fast = eqm.model_onaxis(model)
    for z in (0.02, 0.0762, 0.1, 0.157, 0.4):
        want, got = np.array(on(z)), np.asarray(fast(z))[:5]
        assert np.allclose(got, want, rtol=1e-12, atol=1e-13 * np.abs(want).max())


def test_equilibrium_command_thesis_scene(tmp_path):
    """`levitron equilibrium thesis`: the contract's keys, no NaN, the band and the reason why the
    thesis's top is not in it; --plot writes a picture."""
    import argparse
    import json

    from levitron.runtime.cli.main import _clean
    from levitron.runtime.cli.commands import equilibrium as cmd
    args = argparse.Namespace(scene="thesis", set=[], json=True, plot=str(tmp_path / "eq.png"))
    out = json.loads(json.dumps(_clean(cmd.run(args)), allow_nan=False))
    assert [e["vertically_stable"] for e in out["equilibria"]] == [False, True]
    assert abs(out["equilibria"][0]["z"] - 0.0762) < 1e-6     # the scene's murho has 8 digits
    assert out["z_c"] > 0 and out["max_mass"] > 0.0284
    lo, hi = out["stable_band"]["z"]
    assert lo == pytest.approx(out["z_c"], rel=1e-9) and hi < out["equilibria"][1]["z"]
    assert out["adiabatic_band"] is not None and "outside the stable band" in out["reason"]
    assert (tmp_path / "eq.png").stat().st_size > 1000


@pytest.mark.parametrize("scene_name", ["thesis_stable", "ring_magnet", "square", "loop"])
def test_band_predicate_float_filter_equals_the_exact_route(scene_name):
    """The stable band asks at every height whether some finite spin range is stable; it answers by
    float roots where their margins are wide and by the exact route elsewhere
    (ray_algebra.has_bounded_spin_interval). Same verdict as the exact route (thesis 3.3.11-3.3.16)
    at 400 heights spanning the scene's hovering range, the band edges included."""
    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene(scene_name))
    P = eqm.params_of(model, model.p)
    rep = eqm.equilibria_of(model, model.p, bands=True)
    zs = np.geomspace(0.05, 5.0, 300) * eqm.scale_of(model)
    for band in rep.stable_bands:        # dense around each edge, where the margins vanish
        zs = np.concatenate([zs, np.geomspace(0.98 * band.z[0], 1.02 * band.z[1], 100)])
    seen = {True: 0, False: 0}
    for z in zs:
        ph = np.asarray(model.onaxis(float(z), model.p), float)
        m = -P["mu"] * ph[2] / P["g"]
        if not (m > 0 and P["mu"] * ph[3] > 0):
            continue
        c = ray_algebra.RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, P["A"], P["C"], P["mu"])
        exact = any(hi < math.inf for _, hi in ray_algebra.spin_intervals_discriminant(c))
        assert ray_algebra.has_bounded_spin_interval(c) == exact, (scene_name, z)
        seen[exact] += 1
    assert seen[True] > 10 and seen[False] > 10, seen          # both verdicts were exercised
