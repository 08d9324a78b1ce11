"""runtime/physics/stability/modes.py and resonances.py: the linear modes at the relative equilibrium against
the sleeping top's closed forms (thesis 3.3.3, 3.3.9-3.3.11) and the raw eigenvalues of the
generated Jacobian; the resonances inside the window against the same closed form, their place
under the spin's scaling law, the selection rule by azimuthal number and the explosive criterion;
levitron_toy's three-wave resonance near 213 rad/s."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.model.load import load_model
from levitron.runtime.model.scenes import load_scene
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.physics.stability.modes import BOUNCE, FAST, SLOW, LinearSystem, Mode, Modes
from levitron.runtime.physics.stability.resonances import allowed, explosive, find, m_balance, relation_text, relations
from levitron.runtime.physics.stability.analysis import stability_of
from levitron.runtime.physics.apparatus.tilted_stability import reduced_jacobian


def _top(name: str, *sets: str):
    model = load_model(load_scene(name, list(sets)))
    res = stability_of(model, eigen=False)
    return model, res


@pytest.fixture(scope="module")
def thesis():
    return _top("thesis_stable")


@pytest.fixture(scope="module")
def toy():
    return _top("levitron_toy")


def _closed_form(model, z_s: float, sigma: float) -> tuple[float, np.ndarray]:
    """The bounce sqrt(mu Phi_3 / m) (thesis 3.3.3) and the transverse frequencies signed by their
    sense, sigma rho t_k with t_k the roots of N(t) (thesis 3.3.10-3.3.11), ascending."""
    P = model.pvals()
    m, A, C, mu = P["m"], P["A"], P["C"], P["mu"]
    ph = np.asarray(model.onaxis(z_s), float)
    rho = C / A
    s2 = sigma ** 2 * rho ** 2
    g1, g2, g3 = mu * ph[1] / (s2 * A), mu * ph[2] / (2 * s2 * math.sqrt(m * A)), mu * ph[3] / (2 * s2 * m)
    t = np.roots([1.0, -1.0, g1 + g3, -g3, g1 * g3 - g2 ** 2])
    return math.sqrt(mu * ph[3] / m), np.sort(sigma * rho * t.real) if np.all(abs(t.imag) < 1e-9) else t


def test_the_bounce_is_sqrt_k_over_m_at_every_spin(thesis):
    model, res = thesis
    lo, hi = res.spin_interval
    for sigma in (0.5 * lo, lo * 1.01, math.sqrt(lo * hi), hi * 0.99, 3 * hi):
        md = Modes.of(model, sigma, res.z_s)
        w_z, _ = _closed_form(model, res.z_s, sigma)
        assert md[BOUNCE].frequency == pytest.approx(w_z, rel=1e-10)
        assert md[BOUNCE].sense == 0 and md[BOUNCE].krein == 1 and md[BOUNCE].azimuthal == 0


@pytest.mark.parametrize("where", [0.02, 0.3, 0.7, 0.98])
def test_the_transverse_modes_are_the_roots_of_N(thesis, where):
    """Signed by the sense, the four transverse frequencies are sigma rho t_k (thesis 3.3.11): the
    roots t > 0 turn with the spin."""
    model, res = thesis
    lo, hi = res.spin_interval
    sigma = lo * (hi / lo) ** where
    md = Modes.of(model, sigma, res.z_s)
    _, signed = _closed_form(model, res.z_s, sigma)
    got = np.array([m.signed for m in md.modes[1:]])
    assert np.allclose(got, signed, rtol=1e-9, atol=0)
    assert md.stable and [m.name for m in md.modes] == [BOUNCE, "translation(-1)", "translation(+1)", SLOW, FAST]
    assert [m.krein for m in md.modes] == [1, 1, 1, -1, 1]        # the slow precession: negative energy


def test_the_large_spin_limits(thesis):
    """sigma -> infinity (the sleeping top): the fast precession -> rho sigma and the slow one
    omega C sigma -> mu (Phi_1 - Phi_2^2 / (2 Phi_3)) (the root t ~ g_1 - g_2^2/g_3 of N); both
    errors fall as 1/sigma^2 (the other two roots have left the axis: above the window; at 1e6
    rad/s rounding in the Jacobian, whose entries reach (C sigma)^2 / A, starts to show)."""
    model, res = thesis
    P = model.pvals()
    ph = np.asarray(model.onaxis(res.z_s), float)
    torque = P["mu"] * (ph[1] - ph[2] ** 2 / (2 * ph[3]))
    errors = []
    for sigma in (1e4, 1e5):
        md = Modes.of(model, sigma, res.z_s)
        on = [m for m in md.modes[1:] if m.krein != 0]
        fast = max(on, key=lambda m: m.frequency)
        slow = min(on, key=lambda m: m.frequency)
        assert fast.name == FAST and fast.sense == 1
        errors.append((fast.frequency / (P["C"] / P["A"] * sigma) - 1,
                       slow.signed * P["C"] * sigma / torque - 1))
    assert not md.stable
    for (f1, s1), (f2, s2) in [errors]:
        assert abs(f2) < 1e-5 and abs(s2) < 2e-3
        assert abs(f2) < 0.02 * abs(f1) and abs(s2) < 0.02 * abs(s1)


def test_the_modes_are_the_generated_jacobians_eigenvalues(toy):
    """levitron_toy (in air: the friction set to 0 first) at 210 rad/s: +-i omega of the modes are
    the eigenvalues of the generated full_jac without (zeta, p_zeta), and the CasADi Hessian of the
    generated full_energy is the Jacobian's Jsym^-1 J."""
    model, res = toy
    md = Modes.of(model, 210.0, res.z_s)
    p = without_friction(model, model.p)
    part = model.part("full")
    ls = LinearSystem(model, res.z_s)
    J = reduced_jacobian(np.asarray(model.fast("full_jac", p)(ls.state(210.0))).reshape(part.nx, part.nx),
                         part.states)
    raw = np.sort(np.linalg.eigvals(J).imag)
    ours = np.sort([s * m.frequency for m in md.modes for s in (1, -1)])
    assert np.allclose(raw, ours, rtol=1e-9, atol=1e-9 * raw.max())
    assert md.hessian_residual < 1e-12 and md.hessian_source.startswith("full_energy")
    cheap = Modes.of(model, 210.0, res.z_s, hessian="jacobian")
    assert [m.krein for m in cheap.modes] == [m.krein for m in md.modes]
    assert md.as_json()["modes"][0]["name"] == BOUNCE


def test_below_the_window_the_colliding_pair_leaves_the_axis(toy):
    model, res = toy
    md = Modes.of(model, 0.8 * res.spin_interval[0], res.z_s)
    bad = [m for m in md.modes if m.krein == 0]
    assert not md.stable and len(bad) == 2 and bad[0].growth > 0
    assert bad[0].frequency == pytest.approx(bad[1].frequency, rel=1e-9)


def _closed_form_root(model, z_s, q, a, b):
    """The spin in [a, b] where sum q_k omega_k = 0 (bounce first, then the signed transverse
    frequencies ascending) by the closed form (thesis 3.3.3, 3.3.11) and bisection."""
    def f(s):
        w_z, tr = _closed_form(model, z_s, s)
        return float(np.dot(q, np.concatenate([[w_z], tr])))
    fa = f(a)
    for _ in range(200):
        mid = 0.5 * (a + b)
        if (f(mid) > 0) == (fa > 0):
            a = mid
        else:
            b = mid
    return 0.5 * (a + b)


def test_the_resonances_sit_where_the_closed_form_puts_them(thesis):
    """Every resonance found on thesis_stable is a root of the same relation among the closed-form
    frequencies, to 1e-9 relative."""
    model, res = thesis
    found, sym = find(model, res.z_s, res.spin_interval)
    assert sym == "axial" and found
    names = [BOUNCE, "translation(-1)", "translation(+1)", SLOW, FAST]
    for r in found:
        q = [dict(r.coefficients).get(n, 0) for n in names]
        at = _closed_form_root(model, res.z_s, q, r.spin * (1 - 1e-4), r.spin * (1 + 1e-4))
        assert r.spin == pytest.approx(at, rel=1e-9)
        assert r.m_balance == 0            # an axisymmetric base: the azimuthal numbers balance


def test_a_resonance_moves_as_one_over_C():
    """The transverse frequencies depend on the spin through sigma rho only (thesis 3.3.10-3.3.11),
    the bounce and z_s not at all: a scene with C doubled has every resonance at half the spin."""
    base, res = _top("thesis_stable")
    C = base.pvals()["C"]
    twice, res2 = _top("thesis_stable", f"top.C={2 * C!r}")
    r1, _ = find(base, res.z_s, res.spin_interval)
    r2, _ = find(twice, res2.z_s, res2.spin_interval)
    assert [r.relation for r in r1] == [r.relation for r in r2]
    assert np.allclose([r.spin / 2 for r in r1], [r.spin for r in r2], rtol=1e-9)


def test_the_selection_rule_by_azimuthal_number():
    assert allowed(0, 0) and not allowed(2, 0) and not allowed(4, 0)      # axial: balanced only
    assert allowed(4, 4) and allowed(-4, 4) and not allowed(2, 4)         # four-fold: mod 4
    assert allowed(2, 2) and not allowed(1, 2)                           # two-fold: mod 2
    azimuthal = [0, 1, 1, 1, 1]
    assert m_balance((1, 0, 1, -1, 0), azimuthal) == 0                   # slow = bounce + T(+1)
    assert m_balance((0, 3, 1, 0, 0), azimuthal) == 4
    ps = relations()
    assert all(sum(map(abs, p)) in (3, 4) for p in ps) and (1, 0, 1, -1, 0) in ps
    assert (0, 2, 0, -2, 0) not in ps and (2, 0, 0, -2, 0) not in ps     # a crossing twice over


def _mode(name, w, sense, krein):
    return Mode(name, w, sense, krein, complex(0, w), 0.0, 0 if sense == 0 else 1)


def test_the_explosive_criterion():
    """Cairns 1979: omega_1 = omega_2 + omega_3 (all > 0) is explosive exactly when wave 1's energy
    sign is opposite to waves 2's and 3's."""
    q = (1, 1, -1)                       # bounce + T = S among signed frequencies
    up = [_mode(BOUNCE, 8, 0, 1), _mode("T", 7, 1, 1), _mode("S", 15, 1, -1)]
    assert explosive(q, up)
    assert not explosive(q, [_mode(BOUNCE, 8, 0, 1), _mode("T", 7, 1, 1), _mode("S", 15, 1, 1)])
    assert not explosive(q, [_mode(BOUNCE, 8, 0, 1), _mode("T", 7, 1, -1), _mode("S", 15, 1, -1)])
    # a mode against the spin enters with its frequency's sign: T(-1) at -7 and S at -15
    against = [_mode(BOUNCE, 8, 0, 1), _mode("T", 7, -1, 1), _mode("S", 15, -1, -1)]
    assert explosive((1, -1, 1), against)
    assert relation_text((1, 1, -1), ["bounce", "T", "S"], [0, 1, 1]) == "S = bounce + T"
    assert relation_text((3, 1), ["T-", "T+"], [-1, 1]) == "T+ = 3 T-"


def test_levitron_toy_has_the_explosive_triad_near_213(toy):
    model, res = toy
    found, sym = find(model, res.z_s, res.spin_interval)
    assert sym == "four-fold"
    top = found[0]
    assert top.order == 3 and top.explosive and top.spin == pytest.approx(213.1, abs=0.5)
    assert top.relation == f"{SLOW} = {BOUNCE} + translation(+1)"
    # the four-fold base lets the m-balance 4 through, which an axisymmetric one would not
    assert any(r.m_balance == 4 for r in found)


def test_the_command_prints_modes_and_resonances(capsys):
    assert cli.main(["stability", "levitron_toy", "--spin", "210", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [m["name"] for m in out["modes"]["modes"]][-1] == FAST
    assert out["resonances"][0]["order"] == 3 and out["resonances"][0]["explosive"]
    assert cli.main(["stability", "levitron_toy", "--spin", "210"]) == 0
    text = capsys.readouterr().out
    assert "strongest: 3-wave, explosive, at 213.1 rad/s" in text
    assert "slow precession: 16.59 rad/s" in text and "energy - (Krein)" in text


def test_without_the_full_model_the_8d_matrix_gives_the_same_modes(thesis):
    """A scene with the reduced model only: the transverse matrix (thesis 3.3.5) beside the bounce,
    S = -Jsym J; the same frequencies, senses and energy signs as the generated full model's."""
    model, res = thesis
    small = load_model(load_scene("reduced_only", [f"top.mass={model.pvals()['m']!r}"]))
    a, b = Modes.of(model, 1000.0, res.z_s), Modes.of(small, 1000.0, res.z_s)
    assert b.source.startswith("transverse_matrix")
    assert [(m.name, m.sense, m.krein) for m in a.modes] == [(m.name, m.sense, m.krein) for m in b.modes]
    assert np.allclose([m.frequency for m in a.modes], [m.frequency for m in b.modes], rtol=1e-9)
