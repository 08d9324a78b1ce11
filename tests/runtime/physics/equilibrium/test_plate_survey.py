"""runtime/physics/equilibrium/finder.py plate_survey: one survey of the plate serves every top over it
(thesis 3.3.1: U = m g z + mu Phi_1, the Phi_k the plate's alone), as a launch Monte Carlo uses it."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.runtime.physics.equilibrium import finder as eqm

SCENES = ["thesis", "thesis_stable", "thesis_air", "ring_magnet", "loop", "square", "levitron_toy"]


@pytest.mark.parametrize("name", SCENES)
def test_onaxis_does_not_depend_on_the_tops_mass_or_moment(derived_model, name):
    """The key plate_survey keeps a survey under masks m and mu: that is right only if the
    generated onaxis ignores them, bit for bit, at heights across the plate's scale."""
    model = derived_model(name)
    scale = eqm.scale_of(model)
    other = model.with_params({"m": 3.7 * model.param("m"), "mu": -0.41 * model.param("mu")})
    for z in scale * np.array([0.013, 0.3, 0.77, 1.9, 6.0]):
        assert np.array_equal(eqm.model_onaxis(model)(z), eqm.model_onaxis(model, other)(z))


@pytest.mark.parametrize("name", ["thesis_air", "ring_magnet"])
def test_the_kept_survey_answers_as_a_fresh_one_in_any_order(derived_model, name):
    """Equilibria of tops of several masses and moments from the kept survey equal a fresh
    survey's (bit for bit), whichever top asks first."""
    model = derived_model(name)
    m, mu = model.param("m"), model.param("mu")
    tops = [model.with_params({"m": m * f, "mu": mu * g}) for f, g in
            [(1.0, 1.0), (0.97, 1.01), (1.02, 0.995), (0.5, 1.0), (1.3, 1.2)]]

    def fresh(p):
        P = eqm.params_of(model, p)
        rep = eqm.survey(eqm.model_onaxis(model, p), eqm.scale_of(model, p), eqm.span_of(model)) \
            .report(P["m"], P["g"], P["mu"])
        return [(e.z, e.vertically_stable, e.stiffness) for e in rep.equilibria], rep.z_c, rep.max_mass

    def kept(p):
        rep = eqm.equilibria_of(model, p)
        return [(e.z, e.vertically_stable, e.stiffness) for e in rep.equilibria], rep.z_c, rep.max_mass

    want = [fresh(p) for p in tops]
    before = set(model.__dict__.get("_plate_surveys", {}))
    assert [kept(p) for p in tops] == want
    assert [kept(p) for p in reversed(tops)] == want[::-1]
    assert len(set(model.__dict__["_plate_surveys"]) - before) <= 1     # one plate, one survey
