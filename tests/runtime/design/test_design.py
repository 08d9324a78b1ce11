"""Design optimisation (runtime/design/optimize.py, thesis 3.3): IPOPT optima verified by the grid and the
float routes on two scenes, the scene-key map (runtime/design/scene_keys.py), the constraint grammar,
physical bounds and --write-scene."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from levitron.scene.paths import ROOT
from levitron.scene.load import load_scene
from levitron.runtime.design import optimize as design
from levitron.runtime.design.constraints import Constraint
from levitron.runtime.errors import UserError
from levitron.runtime.model.load import load_model
from levitron.runtime.design.scene_keys import KeyMap, Vary, pvector


@pytest.mark.parametrize("scene, box", [("thesis_stable", "top.mass=0.0505:0.0524"),
                                        ("loop", "top.mass=0.0197:0.0209")])
def test_spin_range_optimum_is_verified(scene, box):
    """The grid's best (20 points, exact float routes) never beats the IPOPT optimum, which the
    float routes reproduce (z_s, sigma_lo, sigma_hi to 1e-8) and which beats the scene's mass."""
    model = load_model(load_scene(scene))
    res = design.optimize(model, [Vary.parse(box)], "spin-range", [Constraint.parse("stiffness>=0.5")])
    ver = res.verification
    assert ver["grid_points"] == 20 and ver["grid_feasible"] >= 1
    assert ver["grid_best"] <= res.value * (1 + 1e-8)
    assert ver["max_relative_gap"] <= 1e-8
    assert res.value == pytest.approx(res.spin_interval[1] - res.spin_interval[0], rel=1e-15)
    assert res.scene_value is not None and res.value >= res.scene_value
    # independent brute force: a finer grid of the float routes does not beat it either
    km = KeyMap(model.scene, model.param_names, [Vary.parse(box)])
    fine = [design.evaluate(model, km, (m,), "spin-range", [Constraint.parse("stiffness>=0.5")])
            for m in np.linspace(Vary.parse(box).lo, Vary.parse(box).hi, 41)]
    assert max(pt.value for pt in fine if pt.value is not None) <= res.value * (1 + 1e-8)
    assert res.stiffness >= 0.5


def test_key_map_is_the_resolvers():
    """plate_current = 2 radius center_field / mu0 (a product of powers), re-resolved exactly."""
    scene = load_scene("loop")
    model_names = ["m", "g", "A", "C", "mu", "plate_a", "plate_current"]
    km = KeyMap(scene, model_names, [Vary.parse("plate.radius=0.04:0.06"),
                                     Vary.parse("plate.center_field=0.008:0.012")])
    j = model_names.index("plate_current")
    assert list(km.E[j]) == [1.0, 1.0] and list(km.E[model_names.index("plate_a")]) == [1.0, 0.0]
    for x in ((0.041, 0.0083), (0.059, 0.0117)):
        _, p = km.exact(x)
        assert np.allclose(km.p(x), p, rtol=1e-12, atol=0)
    # murho without a top moment: plate_rho = -murho, mu fixed at the nominal -1
    th = load_scene("thesis")
    km = KeyMap(th, list(th.params), [Vary.parse("plate.murho=-0.003:-0.002")])
    assert km.E[list(th.params).index("plate_rho"), 0] == 1.0
    assert km.E[list(th.params).index("mu"), 0] == 0.0


def test_bounds_must_be_physical():
    scene = load_scene("thesis")
    with pytest.raises(UserError, match="hole"):
        KeyMap(scene, list(scene.params), [Vary.parse("plate.hole=0.05:0.2")])
    with pytest.raises(UserError, match="straddle"):
        Vary.parse("top.mass=-1:1")
    with pytest.raises(UserError, match="structure"):
        rm = load_scene("ring_magnet")
        KeyMap(rm, list(rm.params), [Vary.parse("plate.r_in=0:0.03")])


def test_constraint_grammar_is_safe():
    assert str(Constraint.parse(" z_s >= 0.05 ")) == "z_s>=0.05"
    for bad in ("__import__('os')>=1", "z_s>0.1", "stiffness>=1;2", "z_s>=nan", "foo>=1"):
        with pytest.raises(UserError):
            Constraint.parse(bad)


def test_objectives_and_their_constraints():
    """The spin objectives need no stiffness floor (tests/cli/test_no_misleading_answers.py); the
    band takes constraints on the scene top's z_s and stiffness only."""
    design.check_objective("spin-range", [])
    design.check_objective("mass-window", [])       # the band needs no stiffness floor
    with pytest.raises(UserError, match="mass-window"):
        design.check_objective("mass-window", [Constraint.parse("sigma_hi>=1")])


def test_mass_window_optimum_is_verified():
    """mass-window (thesis 3.3.3, 3.3.11; the band's edges by runtime/physics/stability/differentiable.py) grows
    with the plate's radius while the scene top's stiffness falls: the optimum sits on the
    stiffness constraint inside the box, verified by the float band (runtime/physics/equilibrium/bands.py) to 1e-8 and
    by the 20-point grid; just beyond it the constraint fails, just inside the window is smaller."""
    model = load_model(load_scene("thesis_stable"))
    box, floor = Vary.parse("plate.radius=0.06:0.14"), [Constraint.parse("stiffness>=3")]
    res = design.optimize(model, [box], "mass-window", floor)
    ver = res.verification
    assert res.solver_status == "Solve_Succeeded" and ver["grid_points"] == 20
    assert ver["grid_best"] <= res.value * (1 + 1e-8) and ver["max_relative_gap"] <= 1e-8
    lo, hi = res.band["mass"]
    assert res.value == pytest.approx((hi - lo) / hi, rel=1e-15)
    assert res.stiffness == pytest.approx(3.0, rel=1e-6)
    x = res.optimum["plate.radius"]
    assert box.lo < x < box.hi
    km = KeyMap(model.scene, model.param_names, [box])
    assert design.evaluate(model, km, (x * (1 + 1e-4),), "mass-window", floor).value is None
    inside = design.evaluate(model, km, (x * (1 - 1e-4),), "mass-window", floor).value
    assert inside is not None and inside < res.value


def test_command_writes_a_scene_that_reads_back(tmp_path):
    out = tmp_path / "best.toml"
    res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "optimize", "loop", "--maximize",
                          "spin-ratio", "--vary", "top.mass=0.0197:0.0209", "--constrain",
                          "stiffness>=0.5", "--write-scene", str(out), "--json"],
                         capture_output=True, text=True, cwd=ROOT, check=False)
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    for key in ("objective", "optimum", "solver_status", "iterations", "verification"):
        assert key in data
    assert {"float_route", "grid_best", "grid_points"} <= set(data["verification"])
    again = load_scene(out)
    # the shortest decimal within a millionth of the optimum (scene_write.shortest), and the scene's name
    written = again.data["top"]["mass"]
    assert written == pytest.approx(data["optimum"]["top.mass"], rel=1e-6) and len(repr(written)) <= 10
    assert 'name = "best"' in out.read_text() and again.name == "best"
    assert pvector(["plate_a"], again)[0] == 0.05


def test_the_shortest_decimal_keeps_the_resolution():
    from levitron.runtime.design.scene_write import shortest
    assert shortest(0.018999999999999996) == 0.019
    assert shortest(0.05187747195948692) == 0.0518775
    assert shortest(1.0) == 1.0 and shortest(-2.5e-7) == -2.5e-7 and shortest(0.0) == 0.0


def test_command_refuses_bad_input(tmp_path):
    for args, word in ((["--maximize", "spin-range", "--vary", "nosuch.key=1:2", "--constrain",
                         "stiffness>=1"], "nosuch"),
                       (["--fit-height", "0.1", "--maximize", "spin-range"], "exactly one"),
                       (["--maximize", "spin-range", "--vary", "top.mass=0.0197:0.0209",
                         "--constrain", "stiffness>=1", "--write-scene", str(tmp_path / "no/x.toml")],
                        "write-scene")):
        res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "optimize", "loop", *args],
                             capture_output=True, text=True, cwd=ROOT, check=False)
        assert res.returncode == 2 and word in res.stderr, (args, res.stderr)
        assert len(res.stderr.strip().splitlines()) == 1


def test_an_answer_is_verified_or_a_one_line_failure():
    """square's spin ratio over the block thickness has a cliff next to the grid's best cell
    (a critical spin enters the interval): either a verified optimum or IPOPT's status, one line."""
    res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "optimize", "square", "--maximize",
                          "spin-ratio", "--vary", "plate.thickness=0.01:0.03", "--constrain",
                          "stiffness>=0.2", "--json"], capture_output=True, text=True, cwd=ROOT,
                         check=False)
    if res.returncode == 0:
        data = json.loads(res.stdout)
        assert data["verification"]["grid_best"] <= data["objective"] * (1 + 1e-8)
    else:
        assert res.returncode == 2 and res.stdout == ""
        assert len(res.stderr.strip().splitlines()) == 1
        assert "IPOPT failed (status " in res.stderr


CANCELLING = """name = "cancelling"
g = 9.81

[top]
mass = 0.012
A = 2.2e-8
C = 1.32e-8
moment = -0.001

[plate]
kind = "expression"
# two disks' potentials whose radii differ by 2 parts in a million: 5-6 digits cancel
phi0 = "-b*(z/sqrt(z**2 + c**2) - z/sqrt(z**2 + (c + d)**2))"

[plate.params]
b = 1.0e5
c = 0.05
d = 1.0e-7

[model]
needs = ["reduced"]
"""


def test_a_formula_too_noisy_for_newton_is_a_one_line_error(tmp_path, capsys):
    """A formula that subtracts nearly equal terms leaves rounding errors (~3e-11) above the strict
    Newton tolerance of the NLP's rootfinders (1e-12): IPOPT cannot start. That is a one-line error
    naming the cause (before: an internal error from CasADi's rootfinder, its dump on stderr)."""
    from levitron.runtime.cli import main as cli
    path = tmp_path / "cancelling.toml"
    path.write_text(CANCELLING)
    argv = ["optimize", str(path), "--maximize", "spin-range", "--vary", "top.mass=0.011:0.013"]
    assert cli.main(argv) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("levitron: ")]
    assert len(err) == 1 and "internal error" not in err[0], err
    assert "rounding errors" in err[0] and "cancellation" in err[0], err
