"""The thesis scene's field strength is the CasADi fit to the thesis's lower equilibrium (7.62 cm)."""
import json
import subprocess
import sys

import pytest

from levitron.scene.paths import ROOT
from levitron.runtime.errors import UserError
from levitron.runtime.design.fit_height import fit_equilibrium_height


def test_thesis_murho_is_the_fit_to_7_62_cm(thesis_model):
    out = fit_equilibrium_height(thesis_model, 0.0762)
    assert out["solver_status"] == "converged"
    murho_scene = thesis_model.scene.data["plate"]["murho"]
    # the scene stores the fit to 8 significant digits
    assert out["optimum"]["murho"] == pytest.approx(murho_scene, rel=5e-8)
    # and the fitted value puts the lower equilibrium exactly there (thesis eq. 3.3.2)
    p = thesis_model.p.copy()
    names = thesis_model.param_names
    p[names.index("mu")] = out["optimum"]["mu"]
    phi2 = thesis_model.onaxis(0.0762, p)[2]
    mg = thesis_model.param("m") * thesis_model.param("g")
    assert abs(mg + p[names.index("mu")] * phi2) < 1e-12 * mg


def test_fit_any_parameter_gives_the_same_product(thesis_model):
    a = fit_equilibrium_height(thesis_model, 0.09, "mu")["optimum"]["murho"]
    b = fit_equilibrium_height(thesis_model, 0.09, "plate_rho")["optimum"]["murho"]
    assert a == pytest.approx(b, rel=1e-12)


def test_fit_bad_input(thesis_model):
    with pytest.raises(UserError, match="positive height"):
        fit_equilibrium_height(thesis_model, -0.1)
    with pytest.raises(UserError, match="not a parameter"):
        fit_equilibrium_height(thesis_model, 0.1, "nonsense")


def test_optimize_command_json():
    res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "optimize", "thesis", "--fit-height",
                          "0.0762", "--json"], cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert {"objective", "optimum", "solver_status"} <= set(out)


def _one_line_error(capsys, *argv) -> str:
    from levitron.runtime.cli.main import main
    rc = main(list(argv))
    out, err = capsys.readouterr()
    assert rc == 2 and out == "", (rc, out, err)
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err


def test_fit_refuses_a_negative_mass(capsys, thesis_model):
    """At 2.62 cm the thesis plate pushes the top down (-mu Phi_2 < 0): the only m with
    m g + mu Phi_2 = 0 is negative. Newton "converges" to it; the fit must refuse, not report it."""
    from levitron.runtime.errors import UserError
    with pytest.raises(UserError, match=r"no physical m .* m = -1\.07"):
        fit_equilibrium_height(thesis_model, 0.0262, "m")
    err = _one_line_error(capsys, "optimize", "thesis", "--fit-height", "0.0262", "--param", "m")
    assert "must be > 0" in err


def test_physical_checks_of_each_kind():
    from levitron.runtime.design.fit_height import physical_problem
    names = ["m", "g", "A", "C", "mu", "plate_a", "plate_w", "plate_rho"]
    ok = [0.03, 9.81, 2.2e-6, 1.32e-6, -1.0, 0.1, 0.03, 0.0026]
    plate = {"kind": "annulus", "radius": 0.1, "hole": 0.03, "murho": -0.0026}
    assert all(physical_problem(plate, names, ok, n) is None for n in names)
    for name, bad, why in (("m", -0.01, "> 0"), ("A", 0.0, "> 0"), ("plate_a", -0.1, "length"),
                           ("plate_w", -0.01, "length"), ("C", 5e-6, "no rigid body")):
        vals = list(ok)
        vals[names.index(name)] = bad
        assert why in physical_problem(plate, names, vals, name)
    vals = list(ok)
    vals[names.index("plate_w")] = 0.0                   # no hole is physical
    assert physical_problem(plate, names, vals, "plate_w") is None


def test_fit_plate_a_errors_are_one_line(capsys):
    """A Newton run that fails (thesis_stable, plate_a at 5 cm) and a name the model lacks
    (ring_magnet has no plate_a) are one-line errors; the latter lists the valid names."""
    err = _one_line_error(capsys, "optimize", "thesis_stable", "--fit-height", "0.05", "--param", "plate_a")
    assert "did not converge" in err
    err = _one_line_error(capsys, "optimize", "ring_magnet", "--fit-height", "0.05", "--param", "plate_a")
    assert "not a parameter" in err and "plate_r_out" in err and "plate_thickness" in err
