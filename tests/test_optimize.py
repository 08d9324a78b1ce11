"""The thesis scene's field strength is the CasADi fit to the thesis's lower equilibrium (7.62 cm)."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from runtime.errors import UserError
from runtime.optimize import fit_equilibrium_height

ROOT = Path(__file__).resolve().parent.parent


def test_thesis_murho_is_the_fit_to_7_62_cm(thesis_model):
    out = fit_equilibrium_height(thesis_model, 0.0762)
    assert out["solver_status"] == "converged"
    murho_scene = thesis_model.scene.data["plate"]["murho"]
    # the scene stores the fit to 8 significant digits
    assert out["optimum"]["murho"] == pytest.approx(murho_scene, rel=5e-8)
    # and the fitted value puts the lower equilibrium exactly there (thesis eq. 3.3.2)
    p = thesis_model.p.copy()
    names = thesis_model.manifest["parameters"]
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
    res = subprocess.run([sys.executable, "-m", "runtime.cli", "optimize", "thesis", "--fit-height",
                          "0.0762", "--json"], cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert {"objective", "optimum", "solver_status"} <= set(out)
