"""Many launches in one call (runtime/scan/batch.py, levitron Study.simulate_many): each run is
the one Study.simulate makes with the same options, bit for bit (status, survival time, final
state), through one call of the C chunk driver on the lane variant of the rhs."""
from __future__ import annotations

import numpy as np
import pytest

import levitron as lev

SPINS = [300.0, 900.0, 1500.0, 2500.0, 4000.0, 1200.0, 700.0, 2000.0, 1800.0]
TILTS = [0.0, 0.05, 0.1, 0.02, 0.2, 0.15, 0.01, 0.3, 0.005]
T_END = 0.5


def _assert_same_as_one_at_a_time(many, one_at_a_time, at=None):
    """Launch at[k] of many (default k) is run k of one_at_a_time, bit for bit."""
    for k, one in enumerate(one_at_a_time):
        i = k if at is None else at[k]
        assert many.status[i] == one.status, i
        assert many.t_survived[i] == one.t_survived, i
        assert many.final_state(i) == one.final_state, i
        assert (None if many.untested[i] else bool(many.levitating[i])) == one.levitating, i


def test_many_launches_equal_simulate_one_at_a_time(study):
    """Spins and tilts where the top floats, falls (left the box) and one on the invariant set
    (tilt 0: untested): 9 launches, not a multiple of the lanes."""
    many = study.simulate_many(SPINS, tilt=TILTS, t_end=T_END)
    assert many.details["lanes"] is True and len(many) == len(SPINS)
    _assert_same_as_one_at_a_time(many, [study.simulate(s, tilt=t, t_end=T_END)
                                         for s, t in zip(SPINS, TILTS)])
    assert {"completed", "left_box"} <= set(many.status.tolist()) and many.untested[0]
    assert many.success and "9 runs ended normally" in many.message
    assert "Simulations(n=9," in repr(many) and "success=True" in repr(many)


def test_a_number_repeats_and_offsets_azimuths_and_vern9_agree(study):
    spins = [1200.0, 1600.0, 2200.0]
    kw = dict(tilt=0.03, offset=[0.0, 0.002, -0.001], tilt_azimuth=1.0, t_end=0.3, integrator="vern9",
              tol=1e-10)
    many = study.simulate_many(spins, **kw)
    assert many.details["integrator"] == "vern9"
    _assert_same_as_one_at_a_time(many, [study.simulate(s, tilt=0.03, offset=o, tilt_azimuth=1.0,
                                                        t_end=0.3, integrator="vern9", tol=1e-10)
                                         for s, o in zip(spins, kw["offset"])])


def test_a_fixed_step_batch_equals_simulate(study):
    many = study.simulate_many([1500.0, 2500.0], tilt=0.05, t_end=0.05, integrator="rk4", step=1e-4)
    assert many.details["lanes"] is False
    _assert_same_as_one_at_a_time(many, [study.simulate(s, tilt=0.05, t_end=0.05, integrator="rk4",
                                                        step=1e-4) for s in (1500.0, 2500.0)])


def test_each_launch_may_have_its_own_scene_keys(study):
    """values={"top.mass": array}: every launch its own parameter vector and hover height, as
    lev.load(scene, {"top.mass": m}).simulate(...)."""
    masses = [0.0512, 0.0515, 0.0518]
    many = study.simulate_many(1500.0, tilt=0.05, t_end=0.3, values={"top.mass": masses})
    assert len(set(many.z_s.tolist())) == 3
    np.testing.assert_array_equal(many.inputs["top.mass"], masses)
    _assert_same_as_one_at_a_time(many, [lev.load("thesis_stable", {"top.mass": m}).simulate(
        1500.0, tilt=0.05, t_end=0.3) for m in masses])


def test_a_mass_that_cannot_hover_is_one_result_with_its_reason(study):
    """values={"top.mass": ...} with masses above the largest the plate holds (0.0524922 kg, z_c):
    those launches are results with the reason simulate gives for that mass, not run; the others
    are simulate's runs bit for bit (issue 26: one such mass failed the whole call)."""
    masses = [0.0512, 0.09, 0.0518, 0.0526]
    many = study.simulate_many(1500.0, tilt=0.05, t_end=0.3, values={"top.mass": masses})
    heavy = [1, 3]
    assert many.status.tolist() == ["completed", "no_hover_height", "completed", "no_hover_height"]
    assert many.success and len(many) == 4
    for i in heavy:
        with pytest.raises(lev.UserError) as one:           # the other route: simulate at that mass
            lev.load("thesis_stable", {"top.mass": masses[i]}).simulate(1500.0, tilt=0.05, t_end=0.3)
        assert many.reason[i] == str(one.value) and "too heavy" in many.reason[i]
        assert not many.levitating[i] and not many.untested[i] and many.t_survived[i] == 0.0
        assert np.isnan(many.z_s[i]) and all(np.isnan(v) for v in many.final_state(i).values())
    assert many.reason[0] is None and many.reason[2] is None
    _assert_same_as_one_at_a_time(many, [lev.load("thesis_stable", {"top.mass": masses[i]}).simulate(
        1500.0, tilt=0.05, t_end=0.3) for i in (0, 2)], at=(0, 2))
    assert "2 runs ended normally" in many.message and "2 cannot hover (the first, launch 1:" in many.message
    assert "cannot hover=2" in repr(many)
    alone = study.simulate_many(1500.0, t_end=0.3, values={"top.mass": [0.09]})   # none runs
    assert alone.status.tolist() == ["no_hover_height"] and alone.details["lanes"] is False


@pytest.mark.parametrize("kw, match", [
    (dict(spin=[1000.0, float("nan")]), "finite"),
    (dict(spin=[1000.0, 1200.0], tilt=[0.1, 0.2, 0.3]), "different lengths"),
    (dict(spin=1000.0, integrator="cvodes"), "C integrators"),
    (dict(spin="fast"), "number"),
    (dict(spin=1000.0, tilt=4.0), "beyond"),
    (dict(spin=1000.0, n_out=5), "unknown"),
    (dict(spin=1000.0, values={"top.colour": [1.0]}), "unknown"),
])
def test_bad_batches_are_one_line_errors(study, kw, match):
    with pytest.raises(lev.UserError, match=match):
        study.simulate_many(**kw)


@pytest.mark.parametrize("scene, options", [
    ("ring_magnet", {"tilt": [0.02, 0.1, 0.3]}),            # its lanes verify now; two of these fall
    ("thesis_air", {"tilt": 0.02}),                          # with friction
    ("reduced_only", {"part": "reduced"}),                  # on the invariant set: untested
])
def test_other_scenes_and_the_reduced_model_equal_simulate(scene, options):
    st = lev.load(scene)
    spins = [800.0, 1500.0, 2500.0]
    many = st.simulate_many(spins, t_end=0.5, **options)
    tilts = options.get("tilt", [None] * 3)
    tilts = tilts if isinstance(tilts, list) else [tilts] * 3
    kw = {k: v for k, v in options.items() if k != "tilt"}
    _assert_same_as_one_at_a_time(many, [st.simulate(s, t_end=0.5, **kw, **({} if t is None else {"tilt": t}))
                                         for s, t in zip(spins, tilts)])
    assert many.details["lanes"] is True


def test_launch_states_are_launch_state_for_each_spin(study):
    """The batch's initial states come from one batched solve per launch position
    (runtime/simulate/start.py launch_states): the states launch_state gives one spin at a time."""
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.simulate.start import launch, launch_state, launch_states
    pt = study.model.part("full")
    la = launch(pt, hover_height(study.model), 0.07, 0.001, study.model.p, 0.4)
    spins = np.linspace(-3000.0, 3000.0, 41)
    np.testing.assert_array_equal(launch_states(la, spins), np.array([launch_state(la, s) for s in spins]))
