"""A magnet off its axis (issue 27, scene key top.moment_tilt): the moment mu (cos b n + sin b e1)
fixed in the body, e1 = R_bs e_x, in the full model (derive/mechanics.py).

The generated terms are checked against the hand form at random states: the energy at rest
U = m g z - mu (cos b n + sin b e1).B(r), with n and e1 written out from the thesis's Tait-Bryan
matrices (eqs. 3.2.2-3.2.5) and B the generated field; Hamilton's equations against CasADi's
derivatives of the generated energy; Euler's equation for the spin, d(L.n)/dt = (m x B).n
= mu sin b B.e2 (e2 = n x e1), from the generated invariants along the generated rhs, an
independent law. At b = 0 the model is the level one.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.scene.inputs import input_hash
from levitron.scene.load import SceneError, load_scene
from tests.helpers.states import random_states

ASKEW = ("top.moment_tilt=0.05",)


@pytest.fixture(scope="module")
def askew(derived_model):
    return derived_model("thesis_stable", *ASKEW)


def body_axes(phi: float, vth: float, zeta: float) -> np.ndarray:
    """The columns e1, e2, n of R_bs = Rx(phi) Ry(vth) Rz(zeta) with the thesis's matrices
    (eqs. 3.2.3-3.2.5: Rx = [[1, 0, 0], [0, c, s], [0, -s, c]], ...), written out by hand."""
    def rx(a):
        return np.array([[1, 0, 0], [0, math.cos(a), math.sin(a)], [0, -math.sin(a), math.cos(a)]])

    def ry(a):
        return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])

    def rz(a):
        return np.array([[math.cos(a), math.sin(a), 0], [-math.sin(a), math.cos(a), 0], [0, 0, 1]])
    return rx(phi) @ ry(vth) @ rz(zeta)


def test_the_energy_at_rest_is_the_hand_form(askew):
    pt = askew.part("full")
    P = askew.pvals()
    b, mu = P["moment_tilt"], P["mu"]
    rng = np.random.default_rng(31)
    for x in random_states(pt, rng):
        rest = x.copy()
        rest[6:] = 0
        R = body_axes(*(rest[pt.index(k)] for k in ("phi", "vartheta", "zeta")))
        n, e1 = R[:, 2], R[:, 0]
        assert np.allclose(askew.call("full_axis", rest), n, rtol=0, atol=1e-15)
        B = askew.field(rest[:3])
        U = P["m"] * P["g"] * rest[2] - mu * (math.cos(b) * n + math.sin(b) * e1) @ B
        scale = P["m"] * P["g"] * rest[2] + abs(mu) * np.linalg.norm(B)
        assert abs(pt.energy(rest) - U) <= 1e-14 * scale
        assert abs(pt.energy(rest, backend="casadi") - U) <= 1e-14 * scale


def test_hamilton_s_equations_are_the_energy_s_derivatives(askew):
    import casadi as ca
    pt = askew.part("full")
    xs, ps = ca.SX.sym("x", pt.nx), ca.SX.sym("p", askew.p.size)
    dH = ca.Function("dH", [xs, ps], [ca.jacobian(askew.casadi("full_energy")(xs, ps), xs)])
    rng = np.random.default_rng(32)
    for x in random_states(pt, rng):
        g = np.asarray(dH(x, askew.p)).ravel()
        want = np.concatenate([g[6:], -g[:6]])
        for backend in ("c", "casadi"):
            got = pt.rhs(x, backend=backend)
            assert np.all(np.abs(got - want) <= 1e-11 * (np.abs(want) + np.abs(want).max() * 1e-6))


def test_the_spin_obeys_euler_s_equation(askew):
    """d(L.n)/dt = (m x B).n = mu sin b B.e2: L.n from full_invariants, differentiated by CasADi
    along the generated rhs; the torque from the hand-written axes and the generated field."""
    import casadi as ca
    pt = askew.part("full")
    P = askew.pvals()
    xs, ps = ca.SX.sym("x", pt.nx), ca.SX.sym("p", askew.p.size)
    Ln = askew.casadi("full_invariants")(xs, ps)[1]
    dLn = ca.Function("dLn", [xs, ps], [ca.jacobian(Ln, xs)])
    rng = np.random.default_rng(33)
    for x in random_states(pt, rng):
        got = float(np.asarray(dLn(x, askew.p)).ravel() @ pt.rhs(x))
        R = body_axes(*(x[pt.index(k)] for k in ("phi", "vartheta", "zeta")))
        torque = P["mu"] * math.sin(P["moment_tilt"]) * R[:, 1] @ askew.field(x[:3])
        assert abs(got - torque) <= 1e-10 * abs(torque)


def test_at_zero_moment_tilt_the_model_is_the_level_one(askew, level):
    pa, pl = askew.part("full"), level.part("full")
    p0 = askew.with_params({"moment_tilt": 0.0})
    rng = np.random.default_rng(34)
    for x in random_states(pa, rng):
        want = pl.rhs(x)
        assert np.all(np.abs(pa.rhs(x, p0) - want) <= 1e-13 * (np.abs(want) + np.abs(want).max() * 1e-6))
        assert abs(pa.energy(x, p0) - pl.energy(x)) <= 1e-14 * abs(pl.energy(x))


def test_the_moment_tilt_is_a_runtime_parameter_and_its_presence_structural():
    one = load_scene("thesis_stable", ["top.moment_tilt=0.01"])
    two = load_scene("thesis_stable", ["top.moment_tilt=-0.2", "plate.tilt=0.001"])
    three = load_scene("thesis_stable", ["top.moment_offset=0.001"])
    assert input_hash(one.data) == input_hash(two.data) != input_hash(three.data)
    assert input_hash(load_scene("thesis_stable").data) != input_hash(one.data)
    assert one.params["moment_tilt"] == 0.01 and one.params["base_tilt"] == 0
    assert one.needs == ("full", "linear") and "moment_tilt" not in load_scene("thesis_stable").params


def test_a_moment_tilt_has_no_reduced_model_and_bad_values_are_one_line():
    with pytest.raises(SceneError, match="breaks the top's own symmetry") as exc:
        load_scene("reduced_only", ["top.moment_tilt=0.01"])
    assert "\n" not in str(exc.value)
    with pytest.raises(SceneError, match=r"\|moment_tilt\| < pi/2"):
        load_scene("thesis_stable", ["top.moment_tilt=2"])
    with pytest.raises(SceneError, match="moment_tilt"):
        load_scene("thesis_stable", ["top.moment_tilt=\"x\""])
    note = load_scene("thesis_stable", ["top.moment_tilt=0.01"]).notes
    assert any("top.moment_tilt: no reduced model" in n for n in note)


def test_the_discriminant_route_says_it_applies_to_an_aligned_apparatus_only(askew):
    from levitron.runtime.physics.stability.analysis import stability_of
    res = stability_of(askew)
    assert res.discriminant == [] and "level, aligned apparatus only" in res.notes[0]
    assert res.as_dict()["routes"]["floquet"] == list(res.spin_interval)
