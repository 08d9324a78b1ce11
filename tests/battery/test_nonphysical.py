"""Non-physical models are refused in one line naming the formula (not answered as physics: "silent
wrong answers"), never answered as physics.

Before: a complex constant (asin(2), acos(1.5), (-8)**(1/3)) passed the parser's "real and finite"
check and became NaN in C; exp(1000) became inf, exp(-1e6) 0; a formula NaN at every height gave
exit 0 with "the field cannot hold a top" (or exit 3 in bands.py).
"""
from __future__ import annotations

import pytest

from levitron.derive.build import render
from levitron.scene.load import SceneError, validate
from levitron.runtime.cli.main import main


def _data(formula: str) -> dict:
    return {"name": "nonphys", "top": {"mass": 0.02, "A": 2.2e-6, "C": 1.32e-6, "moment": -1.0},
            "plate": {"kind": "expression", "phi0": formula, "params": {"b": 1.0}},
            "field": {"order": 2}, "model": {"needs": ["reduced"]}}


@pytest.mark.parametrize("formula,why", [
    ("b*asin(2)*z", "not a real number"), ("b*acos(1.5) + z", "not a real number"),
    ("b*(-8)**(1/3)*z", "not a real number"), ("b*exp(1000)*z", "beyond the range of a double"),
    ("b*z**2*exp(-1e6)", "below the range of a double"), ("b*1e-400*z", "below the range of a double"),
    ("b*z*exp(exp(exp(exp(9))))", "beyond the range of a double"),
])
def test_a_constant_without_a_real_double_is_refused(formula, why):
    with pytest.raises(SceneError) as err:
        render(validate(_data(formula)))
    msg = str(err.value)
    assert msg.startswith("plate.phi0: ") and why in msg and "\n" not in msg, msg


def _scene(tmp_path, formula: str):
    path = tmp_path / "nonphys.toml"
    path.write_text("\n".join([
        'name = "nonphys"', "[top]", "mass = 0.02", "A = 2.2e-6", "C = 1.32e-6", "moment = -1.0",
        "[plate]", 'kind = "expression"', f'phi0 = "{formula}"', "[plate.params]", "b = 1.0",
        "[model]", 'needs = ["reduced"]']) + "\n")
    return str(path)


@pytest.mark.parametrize("command", ["equilibrium", "stability"])
def test_a_model_nan_at_every_height_is_a_one_line_error(command, tmp_path, capsys):
    """sqrt(-1 - z**2) is NaN for every real z: exit 2 naming the formula (before: exit 0 and
    "the field cannot hold a top of mass 0.02")."""
    scene = _scene(tmp_path, "b*sqrt(-1 - z**2)")
    try:
        code = main([command, scene, "--json"])
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    errors = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("levitron: ")]
    assert code == 2 and out == "", (code, out, err)
    assert len(errors) == 1, err
    assert "plate.phi0 = 'b*sqrt(-1 - z**2)'" in errors[0] and "not finite" in errors[0], errors[0]


@pytest.mark.parametrize("bz,needs", [("b*exp(z*z)", "erfi"), ("b*sin(z)/z", "Si"), ("b/log(z + 2)", "li")])
def test_a_bz_whose_antiderivative_has_no_code_is_refused(bz, needs):
    """Found by tests/battery/test_properties.py: bz = exp(z*z) integrates to erfi, which the C printer
    cannot print (before: PrintMethodNotImplementedError, exit 3)."""
    data = _data("z")
    del data["plate"]["phi0"]
    data["plate"]["bz"] = bz
    with pytest.raises(SceneError) as err:
        render(validate(data))
    msg = str(err.value)
    assert msg.startswith("plate.bz = ") and needs in msg and "phi0" in msg and "\n" not in msg, msg


@pytest.mark.parametrize("formula", ["b*atan(log(0))", "b*z + sin(log(0))"])
def test_sympy_failing_on_a_formula_is_a_one_line_refusal(formula):
    """Found by tests/battery/test_properties.py: atan(log(0)) is sympy's AccumBounds(-pi/2, pi/2), which
    passed the parser's "real and finite" check and made derive raise "Only real
    AccumulationBounds are supported" (ValueError, exit 3)."""
    with pytest.raises(SceneError) as err:
        render(validate(_data(formula)))
    assert str(err.value).startswith("plate.phi0: ") and "\n" not in str(err.value)
