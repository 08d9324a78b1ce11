"""The generated invariants (derive/invariants.py: L_z, L.n in canonical variables) against the numpy
route of runtime/simulate/run.py (angular_momentum_z: the generator of rotations about the lab z axis
from the rotation matrices of derive/kinematics.py, by least squares; spin_momentum), at random
states of both coordinate sets: two independent routes to the same Noether momenta (thesis 2.3)."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.runtime.simulate import run as sim, invariants, rotations


@pytest.fixture(scope="module")
def zxz(derived_model):
    return derived_model("thesis_stable", 'model.coordinates="euler-zxz"')


@pytest.mark.parametrize("which", ["thesis_model", "zxz"])
def test_generated_invariants_match_the_numpy_route(which, request):
    model = request.getfixturevalue(which)
    pt = model.part("full")
    rng = np.random.default_rng(11)
    X = rng.uniform(-1, 1, (50, pt.nx)) * np.array([0.01, 0.01, 0.1, 1, 1, 5, 1e-3, 1e-3, 1e-3,
                                                     1e-5, 1e-5, 1e-3])
    X[:, pt.states.index("z")] += 0.12
    if rotations.coordinates_of(pt) == "euler-zxz":
        X[:, pt.states.index("theta")] = rng.uniform(0.2, 1.2, len(X))
    got = model.rows("full_invariants", X)
    want = np.array([[invariants.angular_momentum_z(pt, x), invariants.spin_momentum(pt, x)] for x in X])
    size = np.abs(X[:, 6:]).max(axis=1, keepdims=True) * (1 + np.abs(X[:, :3]).max(axis=1, keepdims=True))
    assert np.all(np.abs(got - want) <= 1e-12 * size + 1e-14 * np.abs(want))
    # one C call over the rows equals the per-state CasADi function
    cas = np.array([np.asarray(model.casadi("full_invariants")(x, model.p)).ravel() for x in X])
    np.testing.assert_allclose(got, cas, rtol=1e-13, atol=1e-13 * np.abs(cas).max())


def test_the_summary_uses_the_generated_invariants(thesis_model, monkeypatch):
    """The summary's invariants come from one C call over the samples (Model.rows), not from the
    per-sample numpy route, and give the same deviations."""
    r = sim.simulate(thesis_model, spin=1000.0, tilt=0.01, t_end=0.05)
    from levitron.runtime.simulate import invariants as inv
    monkeypatch.setattr(inv, "angular_momentum_z", lambda *a: (_ for _ in ()).throw(AssertionError))
    again = sim.simulate(thesis_model, spin=1000.0, tilt=0.01, t_end=0.05)
    assert again["conserved_max_deviation"] == r["conserved_max_deviation"]
    assert r["conserved_max_deviation"]["L_z"] < 1e-8


@pytest.mark.parametrize("which", ["thesis_model", "zxz"])
def test_generated_axis_matches_the_numpy_rotations(which, request):
    """n = R_bs e_z: the generated `full_axis` against runtime/simulate/run.py's numpy mirror of
    derive/kinematics.py's matrices (thesis eqs. 2.1.6-2.1.9, 3.2.2-3.2.5) at random angles."""
    model = request.getfixturevalue(which)
    pt = model.part("full")
    coords = rotations.coordinates_of(pt)
    rng = np.random.default_rng(5)
    X = rng.uniform(-3, 3, (40, pt.nx))
    idx = [pt.states.index(a) for a in rotations.ANGLES[coords]]
    want = np.array([rotations.rotation_bs(coords, x[idx])[:, 2] for x in X])
    np.testing.assert_allclose(model.rows("full_axis", X), want, rtol=0, atol=4e-16)


def test_the_reduced_models_invariants_are_its_column_not_a_loop(thesis_model):
    """The reduced model (no generated invariants: on I both are -p_zeta) gives L_z and L.n as one
    column of the samples, the per-sample numpy route's numbers bit for bit."""
    pt = thesis_model.part("reduced")
    X = np.random.default_rng(3).normal(size=(30, pt.nx))
    want = np.array([[invariants.angular_momentum_z(pt, x), invariants.spin_momentum(pt, x)] for x in X])
    got = invariants.invariants(pt, X, thesis_model.p)
    assert got.shape == (30, 2) and np.array_equal(got, want)


def test_one_run_computes_its_per_sample_quantities_once(thesis_model, monkeypatch):
    """simulate's summary and its trajectory table share one Samples (runtime/simulate/invariants.py):
    the generated invariants and axis are each called once over the samples, and the table's columns
    are those of separate calls, bit for bit."""
    from levitron.runtime.simulate import invariants as inv
    calls = []
    rows = type(thesis_model).rows
    monkeypatch.setattr(type(thesis_model), "rows",
                        lambda self, name, X, p=None: calls.append(name) or rows(self, name, X, p))
    r = sim.simulate(thesis_model, spin=1000.0, tilt=0.01, t_end=0.05)
    assert sorted(calls) == ["full_axis", "full_invariants"]   # the launch needs no rhs (p = M qdot)
    X = np.column_stack([r.trajectory[s] for s in thesis_model.part("full").states])
    pt = thesis_model.part("full")
    both = inv.invariants(pt, X, thesis_model.p)
    assert np.array_equal(r.trajectory["L_z"], both[:, 0])
    assert np.array_equal(r.trajectory["L_n"], both[:, 1])
    assert np.array_equal(r.trajectory["tilt"], inv.tilt_of(pt, X))
