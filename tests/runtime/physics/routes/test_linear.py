"""Linear stability at the relative equilibrium (thesis 3.3): the two routes, the classification near
a critical spin, and the nonlinear model's behaviour inside and outside the interval.
"""
from __future__ import annotations

import math
import random
from fractions import Fraction

import mpmath as mp
import numpy as np
import pytest

from levitron.runtime.physics.routes import eigen_route

from levitron.runtime.physics.routes import ray_algebra

from levitron.runtime.physics.stability import analysis as stability
from levitron.runtime.physics.equilibrium import finder as eqm
from tests.helpers.annulus import (
    A_PLATE,
    A_TOP,
    C_TOP,
    W_PLATE,
    G,
    annulus,
    fitted_murho,
)

MU = fitted_murho()


def hover(onaxis, m, mu=MU, scale=A_PLATE, g=G):
    z = [e.z for e in eqm.vertical_equilibria(onaxis, m, g, mu, scale) if e.vertically_stable][0]
    return z, onaxis(z)


# scenes: (name, onaxis, m, A, C, mu, scale, g); masses chosen inside each plate's stable band
def scenes():
    on = annulus(A_PLATE, W_PLATE)
    disk = annulus(A_PLATE, 0.0)
    mu_disk = -0.0515 * G / disk(0.06)[2]       # a disk whose band holds a ~50 g top
    one = annulus(1.0, 0.3)                       # the thesis plate in units of its radius, g = 1
    mu_one = -1.0 / one(0.762)[2]
    rep = eqm.analyse(disk, 0.05, G, A_TOP, C_TOP, mu_disk, A_PLATE)
    band_disk = rep.stable_band
    rep1 = eqm.analyse(one, 1.0, 1.0, 0.03, 0.05, mu_one, 1.0)
    return [
        ("thesis plate, 51.5 g", on, 0.0515, A_TOP, C_TOP, MU, A_PLATE, G),
        ("thesis plate, 50.5 g", on, 0.0505, A_TOP, C_TOP, MU, A_PLATE, G),
        ("thesis plate, 52.4 g (near z_c)", on, 0.0524, A_TOP, C_TOP, MU, A_PLATE, G),
        ("disk", disk, float(np.mean(band_disk.mass)), A_TOP, C_TOP, mu_disk, A_PLATE, G),
        ("dimensionless", one, float(np.mean(rep1.stable_band.mass)), 0.03, 0.05, mu_one, 1.0, 1.0),
    ]


SCENES = scenes()


@pytest.mark.parametrize("scene", SCENES, ids=[s[0] for s in SCENES])
def test_two_routes_agree(scene):
    """Route "discriminant" (exact) and route "eigenvalues" (8-D Jacobian) give the same spin
    interval to 1e-6 relative (measured ~1e-10)."""
    name, on, m, A, C, mu, scale, g = scene
    res = stability.analyse(on, m, g, A, C, mu, scale)
    assert res.spin_interval is not None, res.reason
    assert len(res.discriminant) == 1 and len(res.eigenvalues) == 1
    assert stability.relative_gap(res.discriminant, res.eigenvalues) <= 1e-6
    assert res.routes_agree


def test_thesis_scene_has_no_interval_by_either_route():
    """The thesis's 28.4 g top at 15.74 cm: both routes find no stable spin, and the answer says why
    (no NaN)."""
    res = stability.analyse(annulus(A_PLATE, W_PLATE), 0.0284, G, A_TOP, C_TOP, MU, A_PLATE)
    assert res.spin_interval is None and res.discriminant == [] and res.eigenvalues == []
    assert "no spin rate" in res.reason
    d = res.as_dict()
    assert d["spin_interval"] is None and d["routes"] == {"discriminant": None, "eigenvalues": None}


def test_too_heavy_answers_plainly():
    _, m_max = eqm.critical_height(annulus(A_PLATE, W_PLATE), G, MU, A_PLATE)
    res = stability.analyse(annulus(A_PLATE, W_PLATE), 1.01 * m_max, G, A_TOP, C_TOP, MU, A_PLATE)
    assert res.spin_interval is None and res.z_s is None and "too heavy" in res.reason


def _mp_four_real(phis, m, A, C, mu, sigma) -> bool:
    """The same polynomial N(t) (thesis 3.3.11) from the same double inputs, in 50-digit arithmetic:
    four real roots? (|Im| below 1e-30 of the root scale; at 1e-12 from a critical rate the
    imaginary parts that do appear are ~1e-9 of it.)"""
    with mp.workdps(50):
        p1, p2, p3, mm, AA, CC, mmu = (mp.mpf(float(v)) for v in (*phis, m, A, C, mu))
        c1 = mmu * p1 * AA / CC ** 2
        c2 = mmu ** 2 * p2 ** 2 * AA ** 3 / (4 * CC ** 4 * mm)
        c3 = mmu * p3 * AA ** 2 / (2 * CC ** 2 * mm)
        s = 1 / mp.mpf(float(sigma)) ** 2
        r = mp.polyroots([1, -1, s * (c1 + c3), -s * c3, s * s * (c1 * c3 - c2)], maxsteps=300,
                         extraprec=300)
        scale = max(abs(x) for x in r)
        return all(abs(mp.im(x)) < mp.mpf(10) ** -30 * scale for x in r)


@pytest.mark.parametrize("scene", SCENES[:3] + SCENES[4:], ids=[s[0] for s in SCENES[:3] + SCENES[4:]])
def test_classification_near_critical_spins_vs_mpmath(scene):
    """Within 1e-7 (and 1e-12) relative of each critical rate the exact classification (Sturm count
    in rational arithmetic) agrees with 50-digit mpmath, on both sides; the eigenvalue route agrees
    at 1e-7 too."""
    name, on, m, A, C, mu, scale, g = scene
    z, ph = hover(on, m, mu, scale, g)
    c = ray_algebra.RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, A, C, mu)
    (lo, hi), = ray_algebra.spin_intervals_discriminant(c)
    for crit in (lo, hi):
        for rel in (1e-7, 1e-12):
            for sgn in (-1, 1):
                sig = crit * (1 + sgn * rel)
                want = _mp_four_real(ph[1:4], m, A, C, mu, sig)
                assert ray_algebra.transverse_stable_exact(c, sig) == want, (crit, rel, sgn)
                assert want == (lo < sig < hi)
                if rel == 1e-7:
                    J = eigen_route.transverse_matrix(ph[1], ph[2], ph[3], m, A, C, mu, sig)
                    assert eigen_route.on_imaginary_axis(J).stable == want


def test_float_discriminant_is_ill_conditioned_near_a_critical_spin():
    """Why the exact formulation: 1e-12 from a critical rate the discriminant G (3.3.12) is ~1e-15
    of the sum of its terms' magnitudes, below the rounding of a float evaluation (32 terms,
    bound 32 * 8 eps * sum|terms|), so its float sign decides nothing there; the exact route still
    agrees with mpmath (previous test)."""
    on, m = annulus(A_PLATE, W_PLATE), 0.0505
    z, ph = hover(on, m)
    c = ray_algebra.RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, A_TOP, C_TOP, MU)
    (lo, hi), = ray_algebra.spin_intervals_discriminant(c)
    sig = lo * (1 + 1e-12)
    c1, c2sq, c3 = c.floats()
    g1, g2sq, g3 = c1 / sig ** 2, c2sq / sig ** 4, c3 / sig ** 2
    terms = [k * g1 ** e1 * g2sq ** (e2 // 2) * g3 ** e3 for k, e1, e2, e3 in ray_algebra.G_TERMS]
    rounding_bound = len(terms) * 8 * np.finfo(float).eps * sum(abs(t) for t in terms)
    assert abs(sum(terms)) < rounding_bound


def test_sturm_count_against_known_roots():
    """The exact Sturm count on polynomials with known roots (distinct, double, complex)."""
    rng = random.Random(11)
    for _ in range(30):
        real = [Fraction(rng.randint(-50, 50), rng.randint(1, 9)) for _ in range(rng.randint(0, 4))]
        npairs = (4 - len(real)) // 2
        poly = [Fraction(1)]
        for r in real:
            poly = np.polymul(poly, [Fraction(1), -r]).tolist()
        for _ in range(npairs):
            a, b = Fraction(rng.randint(-9, 9)), Fraction(rng.randint(1, 9))
            poly = np.polymul(poly, [Fraction(1), -2 * a, a * a + b * b]).tolist()
        assert ray_algebra.sturm_real_root_count(poly) == len(set(real))


def test_critical_spins_are_certified_roots_and_match_L_of_l():
    """Each critical s is a sign change of the exact ray cubic within a few ulps, and the roots of
    the thesis's L(l) (3.3.13, via g21, g31 of 3.3.14) give the same rates by sigma^2 = c1/l
    (the relation g1 = l, thesis 3.3.19-3.3.21)."""
    on, m = annulus(A_PLATE, W_PLATE), 0.0515
    z, ph = hover(on, m)
    c = ray_algebra.RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, A_TOP, C_TOP, MU)
    ints, _ = ray_algebra.ray_cubic_int(c)
    for s in ray_algebra.critical_s(c):
        w = 4 * np.spacing(s)
        assert ray_algebra._exact_sign(ints, s - w) * ray_algebra._exact_sign(ints, s + w) <= 0
    alpha = math.sqrt(A_TOP / m)
    g21 = -alpha * ph[2] / (2 * ph[1])
    g31 = -alpha ** 2 * ph[3] / (2 * ph[1])
    ls = np.roots(ray_algebra.l_cubic(g21, g31)[::-1])
    ls = sorted(float(v.real) for v in ls if abs(v.imag) < 1e-9 * abs(v) and v.real > 0)
    c1 = float(c.c1)
    from_l = sorted(ray_algebra.sigma_of_l(v, c1) for v in ls)
    from_s = sorted(1 / math.sqrt(s) for s in ray_algebra.critical_s(c))
    assert np.allclose(from_l, from_s, rtol=1e-9, atol=0)


def test_eq_3_3_22_3_3_23_approximations_at_z_c():
    """At z_c (g31 = 0) the thesis's sigma_1, sigma_2 (their squares, 3.3.22/3.3.23) approach the
    exact critical rates as g21 -> 0: sigma_1 exact/approx = (1 + g21^2 + 3 g21^4 ...)^(-1/2) from
    the series of l1 (3.3.17), and sigma_2 has relative error ~ g21^2 (from l2, 3.3.18)."""
    on = annulus(A_PLATE, W_PLATE)
    z_c, m_c = eqm.critical_height(on, G, MU, A_PLATE)
    ph = on(z_c)
    approx = ray_algebra.thesis_approximations(ph[1], ph[2], G, m_c, A_TOP, C_TOP)
    g21 = approx["g21"]
    c = ray_algebra.RayCoefficients.from_physics(ph[1], ph[2], ph[3], m_c, A_TOP, C_TOP, MU)
    (lo, hi), = ray_algebra.spin_intervals_discriminant(c)
    assert abs(lo / approx["sigma1"] - (1 + g21 ** 2 + 3 * g21 ** 4) ** -0.5) < 10 * g21 ** 6
    # l2 = 27 g21^2/4 (1 - 9 g21^2 + ...) so sigma_2 exact/approx = 1 + 9 g21^2/2 + O(g21^4)
    assert abs(hi / approx["sigma2"] - (1 + 4.5 * g21 ** 2)) < 100 * g21 ** 4


def test_on_imaginary_axis_tolerance_is_a_real_bound():
    """A Hamiltonian matrix with known imaginary eigenvalues passes; moving a pair off the axis by
    1e3 of its own tolerance fails, by 1e-3 of it passes; the tolerance is tiny against the
    eigenvalues."""
    w1, w2 = 3.0, 7e2
    J = np.zeros((4, 4))
    J[0, 2], J[1, 3], J[2, 0], J[3, 1] = 1.0, 1.0, -w1 ** 2, -w2 ** 2
    ok = eigen_route.on_imaginary_axis(J)
    assert ok.stable and np.all(ok.tolerance < 1e-10 * w2)
    for factor, expect in ((1e3, False), (1e-3, True)):
        shift = factor * ok.tolerance.max()
        J2 = J.copy()
        J2[2, 2] = 2 * shift            # x'' = -w1^2 x + 2 shift x': lambda = shift +- i sqrt(w1^2 - shift^2)
        chk = eigen_route.on_imaginary_axis(J2)
        if not expect:
            assert np.max(chk.eigenvalues.real) == pytest.approx(shift, rel=1e-2)
        assert chk.stable == expect


# ---------------------------------------------------------------- the full generated model

def _with_mass(model, mass):
    names = model.param_names
    p = model.p.copy()
    p[names.index("m")] = mass
    return p, dict(zip(names, p))


def test_full_model_jacobian_routes_agree(thesis_model):
    """Route "eigenvalues" on the generated full_jac (12x12, transverse block after checking the
    decoupling) equals the exact route to 1e-6 relative; the generated block equals the 8-D matrix."""
    p, P = _with_mass(thesis_model, 0.0515)
    on, jac, states = stability.model_callables(thesis_model, p)
    res = stability.analyse(on, P["m"], P["g"], P["A"], P["C"], P["mu"], A_PLATE, jac, states)
    assert res.spin_interval is not None and res.routes_agree
    assert stability.relative_gap(res.discriminant, res.eigenvalues) <= 1e-6
    ph = on(res.z_s)
    sig = float(np.mean(res.spin_interval))
    Jb = eigen_route.transverse_block(jac(eigen_route.full_equilibrium_state(states, res.z_s, P["C"], sig)), states)
    J8 = eigen_route.transverse_matrix(ph[1], ph[2], ph[3], P["m"], P["A"], P["C"], P["mu"], sig)
    assert np.allclose(Jb, J8, rtol=1e-13, atol=1e-13 * np.abs(J8).max())


def _simulate(model, p, states, x0, t_end, tol, box, n_out):
    from levitron.runtime.integrate import run as integrate
    return integrate.integrate(model.part("full"), x0, t_end, "dop853", tol=tol, p=p, box=box,
                               n_out=n_out)


def _thesis_top(thesis_model):
    """The thesis's 51.5 g top: (p, its parameters, the Jacobian, the states, its spin interval,
    z_s, the box |z - z_s| < z_s/2, r < z_s/2 a run must stay in)."""
    from levitron.runtime.integrate import run as integrate
    p, P = _with_mass(thesis_model, 0.0515)
    on, jac, states = stability.model_callables(thesis_model, p)
    res = stability.analyse(on, P["m"], P["g"], P["A"], P["C"], P["mu"], A_PLATE, jac, states)
    z_s = res.z_s
    box = integrate.Box(states.index("z"), 0.5 * z_s, 1.5 * z_s, states.index("x"), states.index("y"), 0.5 * z_s)
    return p, P, jac, states, res.spin_interval, z_s, box


def test_nonlinear_top_stays_up_inside_the_interval(thesis_model):
    """Started 5 % inside the interval (both ends) with a tilt of 1e-3 rad and an offset of 1e-3 z_s,
    the full nonlinear model keeps the top up for 20 s (no exit from the box |z - z_s| < z_s/2,
    r < z_s/2) and the offset stays small (< 5 % of z_s)."""
    p, P, jac, states, (lo, hi), z_s, box = _thesis_top(thesis_model)
    ix, iy = states.index("x"), states.index("y")
    for sig in (1.05 * lo, 0.95 * hi):
        x0 = eigen_route.full_equilibrium_state(states, z_s, P["C"], sig)
        x0[ix] = 1e-3 * z_s
        x0[states.index("vartheta")] = 1e-3
        out = _simulate(thesis_model, p, states, x0, 20.0, 1e-10, box, 2000)
        assert out.status == "completed" and out.t_final == pytest.approx(20.0)
        assert np.max(np.hypot(out.X[:, ix], out.X[:, iy])) < 0.05 * z_s


def test_nonlinear_growth_rate_outside_the_interval(thesis_model):
    """Outside the interval (10 % below and above) an offset of 1e-9 z_s grows at the rate of the
    largest real part of the Jacobian's eigenvalues, within 20 % (fit of log r(t) while r grows
    from 1e2 to 1e5 times its start; measured within 0.2 %)."""
    p, P, jac, states, (lo, hi), z_s, box = _thesis_top(thesis_model)
    ix, iy = states.index("x"), states.index("y")
    for sig in (0.9 * lo, 1.1 * hi):
        x_eq = eigen_route.full_equilibrium_state(states, z_s, P["C"], sig)
        gamma = eigen_route.growth_rate(eigen_route.transverse_block(jac(x_eq), states))
        assert gamma > 0
        r0 = 1e-9 * z_s
        x0 = x_eq.copy()
        x0[ix] = r0
        t_end = math.log(1e6) / gamma
        out = _simulate(thesis_model, p, states, x0, t_end, 1e-11, box, 4000)
        r = np.hypot(out.X[:, ix], out.X[:, iy])
        sel = (r > 1e2 * r0) & (r < 1e5 * r0)
        assert sel.sum() > 50
        rate = np.polyfit(out.t[sel], np.log(r[sel]), 1)[0]
        assert abs(rate / gamma - 1) < 0.2, (sig, rate, gamma)


# ---------------------------------------------------------------- the command

def _run_stability(sets):
    import argparse
    import json

    from levitron.runtime.cli.main import _clean
    from levitron.runtime.cli.commands import stability as cmd
    args = argparse.Namespace(scene="thesis", set=sets, json=True, height=None)
    out = _clean(cmd.run(args))
    text = json.dumps(out, allow_nan=False)      # never NaN or inf in the JSON
    return json.loads(text)


def test_stability_command_thesis_scene(thesis_model):
    """`levitron stability thesis`: z_s, spin_interval null with a reason (the top hovers outside the
    stable band), both routes null, the approximations at z_c as rates with Hz beside."""
    out = _run_stability([])
    for key in ("z_s", "spin_interval", "routes", "approximations"):
        assert key in out
    assert out["spin_interval"] is None and out["reason"]
    assert out["routes"] == {"discriminant": None, "eigenvalues": None}
    a = out["approximations"]
    assert a["sigma1"] > 0 and a["sigma2"] > a["sigma1"]
    assert a["sigma1_hz"] == pytest.approx(a["sigma1"] / (2 * math.pi), rel=1e-15)


def test_stability_command_inside_the_band(thesis_model):
    """With a 51.5 g top the command reports the interval in rad/s with Hz and rpm beside, both
    routes agreeing to 1e-6."""
    out = _run_stability(["top.mass=0.0515"])
    lo, hi = out["spin_interval"]
    assert 0 < lo < hi
    assert out["spin_interval_hz"] == pytest.approx([lo / (2 * math.pi), hi / (2 * math.pi)], rel=1e-15)
    assert out["spin_interval_rpm"] == pytest.approx([30 * lo / math.pi, 30 * hi / math.pi], rel=1e-15)
    d, e = out["routes"]["discriminant"], out["routes"]["eigenvalues"]
    assert stability.relative_gap([tuple(d)], [tuple(e)]) <= 1e-6
    assert out["eigen_source"].startswith("full_jac")
