"""The prepared run (runtime/integrate/propagator.py, Study.propagator): the same numbers as
integrate(), bit for bit, for every adaptive C method; bad input refused in one line, nothing lost.
Its speed is measured by `levitron bench` (per_call in reports/<scene>/bench_reduced.json), not here."""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.propagator import Propagator
from levitron.runtime.integrate.run import integrate


@pytest.mark.parametrize("method", ["dop853", "vern9", "taylor", "auto"])
def test_same_final_state_as_integrate_bit_for_bit(study, method):
    prop = study.propagator("reduced", method, 1e-10, spin=1100.0)
    part = study.model.part("reduced")
    x0 = np.array([0.108, 0.0, 0.001, prop.scale[3] * 0.9])
    for t_end in (0.05, 0.4, 0.05):
        got = prop(x0, t_end)
        ref = integrate(part, x0, t_end, method=method, tol=1e-10, scale=prop.scale, n_out=1)
        assert ref.status == "completed"
        np.testing.assert_array_equal(got, ref.x_final)
        assert prop.status == "completed" and prop.steps == ref.steps
        prop.state[:] = x0                                   # the in-place form: the same run
        prop.propagate(t_end)
        np.testing.assert_array_equal(prop.state, ref.x_final)
    assert prop.states == ("z", "zeta", "p_z", "p_zeta")


def test_the_full_model_too(study):
    prop = study.propagator("full", "dop853", 1e-9, spin=1100.0)
    part = study.model.part("full")
    from levitron.runtime.simulate.start import initial_state
    x0 = initial_state(part, 0.106, 1100.0, 0.01, 0.001, study.model.p)
    ref = integrate(part, x0, 0.02, method="dop853", tol=1e-9, scale=prop.scale, n_out=1)
    np.testing.assert_array_equal(prop(x0, 0.02), ref.x_final)
    with pytest.raises(UserError, match="reduced model only"):
        study.propagator("full", "taylor")


@pytest.mark.parametrize("call, words", [
    (lambda p: p([0.1, 0.0, 0.0], 0.1), "4 numbers"),
    (lambda p: p([math.nan, 0.0, 0.0, 0.0], 0.1), "not finite"),
    (lambda p: p([0.1, 0.0, 0.0, 0.0], -1.0), "positive finite"),
    (lambda p: p([0.1, 0.0, 0.0, 0.0], math.inf), "positive finite"),
])
def test_bad_input_is_one_line_and_the_next_run_is_unharmed(study, call, words):
    prop = study.propagator("reduced", "dop853", 1e-9)
    x0 = np.array([0.108, 0.0, 0.0, 1e-3])
    before = prop(x0, 0.1)
    with pytest.raises(UserError, match=words) as info:
        call(prop)
    assert "\n" not in str(info.value)
    np.testing.assert_array_equal(prop(x0, 0.1), before)


def test_a_run_that_cannot_finish_says_why(study):
    part = study.model.part("reduced")
    prop = Propagator(part, "dop853", 1e-9, scale=np.ones(4), max_steps=2)
    with pytest.raises(UserError, match="ended 'step_budget'"):
        prop([0.108, 0.0, 0.0, 1e-3], 1.0)


@pytest.mark.parametrize("kwargs, words", [
    (dict(method="rk4"), "adaptive C method"), (dict(method="cvodes"), "adaptive C method"),
    (dict(tol=1.0), "too loose"), (dict(scale=None), "needs scale"),
    (dict(scale=[1.0, 1.0]), "4 positive numbers"), (dict(method="leapfrog"), "unknown integrator"),
])
def test_bad_options_are_refused(study, kwargs, words):
    args = dict(method="dop853", tol=1e-9, scale=np.ones(4)) | kwargs
    with pytest.raises(UserError, match=words):
        Propagator(study.model.part("reduced"), **args)


def test_parameters_change_in_place_and_scale_is_fixed(study):
    """prop.p[:] = ... is the next run's parameter vector (as integrate(p=...) would use it)."""
    prop = study.propagator("reduced", "dop853", 1e-10)
    part = study.model.part("reduced")
    x0 = np.array([0.108, 0.0, 0.0, 1e-3])
    p2 = study.p_of({"top.mass": 0.0512})
    prop.p[:] = p2
    ref = integrate(part, x0, 0.3, method="dop853", tol=1e-10, p=p2, scale=prop.scale, n_out=1)
    np.testing.assert_array_equal(prop(x0, 0.3), ref.x_final)
    buf = prop.p                 # assignment copies into the vector C reads, never rebinds it
    prop.p = 2 * p2
    assert prop.p is buf and np.array_equal(buf, 2 * p2)
    with pytest.raises(ValueError):
        prop.scale[0] = 1.0


@pytest.mark.parametrize("part", ["reduced", "full"])
def test_a_box_stops_a_fall_where_simulates_box_does(study, part):
    """Study.propagator(box=True): simulate's box (|z - z_s|, r within z_s / 2). A top started far
    below its hover height falls out of it: the run stops at the crossing with status left_box, the
    state and time of integrate() with the same Box, bit for bit, and no error; the next run, inside
    the box, completes. Without a box the same fall is integrated to t_end."""
    from levitron.runtime.simulate.start import default_box, initial_state
    from levitron.runtime.physics.equilibrium.finder import hover_height
    pt = study.model.part(part)
    z_s = hover_height(study.model, study.model.p)
    prop = study.propagator(part, "dop853", 1e-9, spin=1100.0, box=True)
    tilt = 0.01 if part == "full" else 0.0
    x0 = initial_state(pt, 0.8 * z_s, 1100.0, tilt, 0.0, study.model.p)    # falls below z_s / 2
    bx = default_box(pt, z_s)
    ref = integrate(pt, x0, 2.0, method="dop853", tol=1e-9, scale=prop.scale, n_out=1, box=bx)
    assert ref.status == "left_box"
    got = prop(x0, 2.0)
    assert prop.status == "left_box" and prop.t_final == ref.t_final < 2.0
    np.testing.assert_array_equal(got, ref.x_final)
    inside = initial_state(pt, z_s, 1100.0, tilt, 0.0, study.model.p)
    prop(inside, 0.05)
    assert prop.status == "completed" and prop.t_final == 0.05
    free = study.propagator(part, "dop853", 1e-9, spin=1100.0)
    free(x0, 0.05)
    assert free.status == "completed" and free.box is None
    half = study.propagator(part, "dop853", 1e-9, spin=1100.0, box=0.1 * z_s)
    assert half.box.z_lo == pytest.approx(0.9 * z_s) and "box z" in repr(half)
    with pytest.raises(UserError, match="box"):
        study.propagator(part, box=-1.0)


def test_a_start_outside_the_box_ends_at_once(study):
    """A sweep gets an answer for every start: outside the box the run ends at t = 0, left_box, with
    the state unchanged (simulate refuses such a start in one line instead)."""
    from levitron.runtime.physics.equilibrium.finder import hover_height
    z_s = hover_height(study.model, study.model.p)
    prop = study.propagator("reduced", "dop853", 1e-9, spin=1100.0, box=0.1 * z_s)
    x0 = np.array([0.7 * z_s, 0.0, 0.0, prop.scale[3] * 0.9])
    np.testing.assert_array_equal(prop(x0, 1.0), x0)
    assert prop.status == "left_box" and prop.t_final == 0.0
    with pytest.raises(UserError, match="already outside the box"):
        study.simulate(1100.0, offset=0.5 * z_s, box=0.1 * z_s, t_end=0.1)
