"""The public Python API (levitron) and the examples/ scripts that use it."""
from __future__ import annotations

import dataclasses
import subprocess
import sys

import pytest

import levitron as lev
from levitron.scene.paths import ROOT
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.stability.analysis import stability_of

EXAMPLES = sorted((ROOT / "examples").glob("*.py"))


@pytest.fixture(scope="module")
def study():
    return lev.load("thesis_stable", {"top.mass": 0.0512})


def test_load_with_overrides_by_scene_key(study):
    assert study.value("top.mass") == 0.0512
    assert study.model.param("m") == 0.0512
    p = study.p_of({"plate.hole": 0.02})
    assert p[study.model.param_names.index("plate_w")] == 0.02


def test_results_are_typed_and_agree_with_the_runtime(study):
    eq = study.equilibria()
    st = study.stability()
    assert dataclasses.is_dataclass(eq) and dataclasses.is_dataclass(st)
    rep = eqm.equilibria_of(study.model)
    assert eq.z_c == rep.z_c and [e.z for e in eq.equilibria] == [e.z for e in rep.equilibria]
    assert st.spin_interval == tuple(stability_of(study.model).spin_interval)
    assert st.stiffness > 0


def test_casadi_functions_have_named_inputs_and_outputs(study):
    f = study.functions()
    assert f["spin"].name_in() == ["z_guess", "sigma_lo_guess", "sigma_hi_guess", "p"]
    assert f["spin"].name_out() == ["z_s", "sigma_lo", "sigma_hi"]
    assert "onaxis" in f and f["z_c"].name_out() == ["z_c", "max_mass"]


def test_gradient_by_scene_key_is_the_chain_rule(study):
    """d z_s / d top.mass = d z_s / d m (identity map) = -g / (mu Phi_3) (thesis 3.3.2 differentiated)."""
    g = study.gradient("z_s", ["top.mass"])["top.mass"]
    st = study.stability()
    assert g == pytest.approx(-study.model.param("g") / st.stiffness, rel=1e-9)


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_examples_run(path):
    res = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, cwd=ROOT,
                         check=False, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.strip()
