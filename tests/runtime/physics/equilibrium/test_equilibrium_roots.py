"""The one equilibrium finder (runtime/physics/equilibrium/finder.py; thesis 3.3.2-3.3.3) on the cases the old
per-command z grids got wrong, through every command that needs an equilibrium:

* two roots a fraction 1e-3, 1e-6, 1e-9 (relative) of the mass below the plate's maximum lie on
  either side of z_c, ~ sqrt(2 delta) z_c apart: `equilibrium`, `stability` (the `analyse` path, which
  said "too heavy" on its coarser grid), `hover_height` (simulate, scan), bench's start and optimize
  all find them, in the SI thesis scene and in a dimensionless scene (g = 1, lengths ~ 1);
* a mass equal to the maximum is one double root, marginal, never vertically stable;
* a pole of an expression plate (phi0 = "rho/(z - b)") is named as a singularity, never returned
  as an equilibrium (it was: "vertically stable, stiffness 2.5e63");
* a NaN stretch (phi0 = "rho*sqrt(z - b)") hides no root just above it (it did: "no root").

Closed forms make the finder's own tests fast; the generated models check the commands.
"""
from __future__ import annotations

import argparse
import json
import math

import numpy as np
import pytest

from levitron.runtime.bench import work_precision as bench

from levitron.runtime.design import fit_height as optimize
from levitron.runtime.scan.stability_map import scan
from levitron.runtime.simulate.run import simulate
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.cli.main import _clean
from levitron.runtime.errors import UserError
from tests.helpers.dimensionless import SCENE as DIMENSIONLESS
from tests.helpers.annulus import A_PLATE, W_PLATE, G, annulus, fitted_murho

EPS = np.finfo(float).eps
DELTAS = (1e-3, 1e-6, 1e-9)

UNIT_SCENE = DIMENSIONLESS      # g = 1, plate radius 1, a top of mass 1 inside the stable band

EXPR_SCENE = """name = "{name}"
g = 1.0

[top]
mass = 1.0
A = 0.01
C = 0.006
moment = {moment}

[plate]
kind = "expression"
phi0 = "{phi0}"

[plate.params]
rho = {rho!r}
b = {b!r}

[field]
order = 2

[model]
needs = ["reduced"]
"""
# the pole: F = 1 - 2 rho / (z - b)^3 (mu = -1) has one root, b + (2 rho)^(1/3), and changes sign
# across z = b; b is no length key, so the grid (scale 1) does not sample b itself
POLE = {"name": "pole_b", "moment": -1.0, "phi0": "rho/(z - b)", "rho": 1.0, "b": 0.77}
# the NaN stretch: Phi_2 = -rho/4 (z - b)^-3/2 is NaN below b; with mu = 1 the root is at
# z - b = (rho/4)^(2/3) = 5e-5, inside the grid cell that straddles b
NAN = {"name": "nan_below_b", "moment": 1.0, "phi0": "rho*sqrt(z - b)", "rho": 4 * 5e-5 ** 1.5, "b": 0.5}


def _write(tmp_path_factory, name: str, text: str) -> str:
    path = tmp_path_factory.mktemp("scenes") / f"{name}.toml"
    path.write_text(text)
    return str(path)


def _load(path: str):
    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    return load_model(load_scene(path))


@pytest.fixture(scope="module")
def unit_scene(tmp_path_factory):
    return _write(tmp_path_factory, "unit_annulus", UNIT_SCENE)


@pytest.fixture(scope="module")
def scenes(unit_scene, thesis_model):
    """{label: (scene argument, loaded model)} for the SI thesis scene and the dimensionless one."""
    return {"si": ("thesis", thesis_model), "unit": (unit_scene, _load(unit_scene))}


def _run(command: str, scene: str, *sets: str, **kw) -> dict:
    import importlib
    cmd = importlib.import_module(f"levitron.runtime.cli.commands.{command}")
    args = argparse.Namespace(scene=scene, set=list(sets), json=True, **kw)
    return json.loads(json.dumps(_clean(cmd.run(args)), allow_nan=False))


# ------------------------------------------------------------------ closed forms: the finder itself

def _closed(units: str):
    """(onaxis, g, mu, scale): the thesis annulus in SI, or the same shape with radius 1, g = 1."""
    if units == "si":
        return annulus(A_PLATE, W_PLATE), G, fitted_murho(), A_PLATE
    return annulus(1.0, 0.3, 0.51915), 1.0, -1.0, 1.0


@pytest.mark.parametrize("units", ["si", "unit"])
@pytest.mark.parametrize("delta", DELTAS)
def test_close_roots_closed_form(units, delta):
    """Two roots, one on each side of z_c, where the quadratic model of F about z_c puts them:
    F(z) = -g delta m_max + mu Phi_4(z_c) (z - z_c)^2 / 2 + O((z - z_c)^3), so z - z_c = +-d,
    d = sqrt(2 g delta m_max / |mu Phi_4(z_c)|), up to the cubic term (relative ~ d / z_c);
    F vanishes at each to rounding of its terms."""
    on, g, mu, scale = _closed(units)
    sv = eqm.survey(on, scale)
    z_c, m_max = sv.critical(g, mu)
    m = m_max * (1 - delta)
    eqs = sv.equilibria(m, g, mu)
    assert len(eqs) == 2, eqs
    lo, hi = eqs
    assert lo.z < z_c < hi.z
    assert not lo.vertically_stable and hi.vertically_stable
    assert not lo.marginal and not hi.marginal
    d = math.sqrt(2 * g * delta * m_max / abs(mu * on(z_c)[4]))
    for z in (hi.z - z_c, z_c - lo.z):
        assert abs(z - d) <= 2 * (d / z_c) * d, (z, d)
    for e in eqs:
        assert abs(m * g + mu * on(e.z)[2]) <= 4 * EPS * m * g


@pytest.mark.parametrize("units", ["si", "unit"])
def test_double_root_at_the_max_mass_is_one_marginal_equilibrium(units):
    on, g, mu, scale = _closed(units)
    sv = eqm.survey(on, scale)
    z_c, m_max = sv.critical(g, mu)
    (e,) = sv.equilibria(m_max, g, mu)
    assert e.z == z_c and e.marginal and not e.vertically_stable
    assert sv.equilibria(m_max * (1 + 1e-12), g, mu) == []
    rep = sv.report(m_max * (1 + 1e-12), g, mu)
    assert "too heavy" in rep.no_hover_reason(m_max * (1 + 1e-12))


def _pole(b: float, rho: float):
    """Phi_k of Phi_0 = rho / (z - b): (-1)^k k! rho / (z - b)^(k+1)."""
    return lambda z: [rho * (-1) ** k * math.factorial(k) / (z - b) ** (k + 1) for k in range(5)]


@pytest.mark.parametrize("b", [1.0, 0.77])
def test_pole_is_a_singularity_not_an_equilibrium(b):
    """b = 1.0 lies on the grid (the onaxis raises there: a point singularity); 0.77 inside a cell
    (F changes sign across it). Either way: one pole named, one root, b + 2^(1/3)."""
    sv = eqm.survey(_pole(b, 1.0), 1.0)
    rep = sv.report(1.0, 1.0, -1.0)
    assert [e.z for e in rep.equilibria] == pytest.approx([b + 2 ** (1 / 3)], rel=1e-14)
    assert rep.equilibria[0].vertically_stable
    (s,) = rep.singularities
    assert s.kind == "pole" and s.z == pytest.approx(b, rel=1e-14)


@pytest.mark.parametrize("root_gap", [5e-5, 0.4])
def test_nan_stretch_hides_no_root(root_gap):
    """Phi_0 = rho sqrt(z - b) is NaN below b = 0.5 (math.sqrt raises: NaN row); the root at
    b + root_gap is found, also inside the grid cell that straddles b."""
    b = 0.5
    rho = 4 * root_gap ** 1.5
    coef = [1, 0.5, -0.25, 3 / 8, -15 / 16]
    on = lambda z: [rho * coef[k] * math.sqrt(z - b) ** (1 - 2 * k) for k in range(5)]
    rep = eqm.survey(on, 1.0).report(1.0, 1.0, 1.0)
    assert [e.z for e in rep.equilibria] == pytest.approx([b + root_gap], rel=1e-12)
    (s,) = rep.singularities
    assert s.kind == "nan" and s.z == 0.0 and s.z_end == pytest.approx(b, rel=1e-15)


# ---------------------------------------------------------- generated models: every command

@pytest.mark.parametrize("units", ["si", "unit"])
@pytest.mark.parametrize("delta", DELTAS)
def test_close_roots_every_command(scenes, units, delta):
    scene, model = scenes[units]
    base = eqm.equilibria_of(model)
    z_c, m_max = base.z_c, base.max_mass
    m = m_max * (1 - delta)
    p = model.with_params({"m": m})
    # the finder, model level
    rep = eqm.equilibria_of(model, p)
    lo, hi = rep.equilibria
    assert lo.z < z_c < hi.z and hi.vertically_stable and not lo.vertically_stable
    assert (rep.z_c, rep.max_mass) == (z_c, m_max)
    # hover_height (simulate, scan)
    assert eqm.hover_height(model, p) == hi.z
    # the commands: equilibrium and stability (the `analyse` path)
    eq = _run("equilibrium", scene, f"top.mass={m!r}", plot=None)
    assert [e["z"] for e in eq["equilibria"]] == [lo.z, hi.z]
    st = _run("stability", scene, f"top.mass={m!r}", height=None)
    assert st["z_s"] == hi.z, st["reason"]
    lo_s, hi_s = st["spin_interval"]
    # bench's start: the scene's top at its own height, spinning inside its interval
    su = bench.setup(model, p)
    assert su.z_s == hi.z and lo_s < su.spin < hi_s
    # simulate and scan start from that height too (a short run: where it starts is the point)
    spin = math.sqrt(lo_s * hi_s)
    run = simulate(model, spin=spin, tilt=1e-3, t_end=2 * math.pi / spin * 20, params={"m": m})
    assert run["z_s"] == hi.z
    res = scan(model, np.array([spin]), "mass", np.array([m]),
               t_end=2 * math.pi / spin * 20, quiet=True)
    assert res.linear[0]["z_s"] == hi.z and res.status[0][0] != "no_hover_height"
    # optimize: fitting m to the upper root gives this mass back, with both roots
    out = optimize.fit_equilibrium_height(model, hi.z, "m")
    assert out["optimum"]["m"] == pytest.approx(m, rel=1e-13)
    assert [e["z"] for e in out["equilibria"]] == pytest.approx([lo.z, hi.z], rel=1e-10)
    assert out["z_star_vertically_stable"]


@pytest.mark.parametrize("units", ["si", "unit"])
def test_max_mass_is_marginal_in_every_command(scenes, units):
    scene, model = scenes[units]
    m_max = eqm.equilibria_of(model).max_mass
    p = model.with_params({"m": m_max})
    (e,) = eqm.equilibria_of(model, p).equilibria
    assert e.marginal and not e.vertically_stable
    with pytest.raises(UserError, match="exactly as heavy"):
        eqm.hover_height(model, p)
    eq = _run("equilibrium", scene, f"top.mass={m_max!r}", plot=None)
    assert [(x["marginal"], x["vertically_stable"]) for x in eq["equilibria"]] == [(True, False)]
    st = _run("stability", scene, f"top.mass={m_max!r}", height=None)
    assert st["z_s"] is None and "double root" in st["reason"]
    st = _run("stability", scene, f"top.mass={m_max * (1 + 1e-9)!r}", height=None)
    assert st["z_s"] is None and "too heavy" in st["reason"]


# ----------------------------------------------------------- expression plates: poles and NaN

@pytest.fixture(scope="module")
def pole_scene(tmp_path_factory):
    return _write(tmp_path_factory, POLE["name"], EXPR_SCENE.format(**POLE))


@pytest.fixture(scope="module")
def nan_scene(tmp_path_factory):
    return _write(tmp_path_factory, NAN["name"], EXPR_SCENE.format(**NAN))


def test_expression_pole_is_named_not_an_equilibrium(pole_scene):
    out = _run("equilibrium", pole_scene, plot=None)
    want = POLE["b"] + (2 * POLE["rho"]) ** (1 / 3)
    assert [e["z"] for e in out["equilibria"]] == pytest.approx([want], rel=1e-13)
    assert [s["kind"] for s in out["singularities"]] == ["pole"]
    assert out["singularities"][0]["z"] == pytest.approx(POLE["b"], rel=1e-14)
    assert eqm.hover_height(_load(pole_scene)) == pytest.approx(want, rel=1e-13)


def test_expression_nan_stretch_hides_no_root(nan_scene):
    out = _run("equilibrium", nan_scene, plot=None)
    want = NAN["b"] + (NAN["rho"] / 4) ** (2 / 3)
    assert [e["z"] for e in out["equilibria"]] == pytest.approx([want], rel=1e-12)
    assert [(s["kind"], s["z"]) for s in out["singularities"]] == [("nan", 0.0)]
    assert out["singularities"][0]["z_end"] == pytest.approx(NAN["b"], rel=1e-15)
