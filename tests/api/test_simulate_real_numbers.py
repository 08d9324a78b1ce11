"""The API's simulate and simulate_many take real, finite numbers only: a complex number or NumPy
array (whose imaginary part NumPy would drop with a warning), NaN or inf is refused in one line
naming the argument (levitron/arguments.py real_column), before any run."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import levitron as lev
from levitron import UserError


@pytest.fixture(scope="module")
def study():
    return lev.load("thesis_stable")


def _refused(call) -> str:
    with warnings.catch_warnings():
        warnings.simplefilter("error")            # a ComplexWarning would be the silent cast
        with pytest.raises(UserError) as exc:
            call()
    text = str(exc.value)
    assert "\n" not in text, text
    return text


@pytest.mark.parametrize("kwargs, name, says", [
    ({"spin": np.array([1000 + 1j, 1100])}, "spin", "complex value (1000+1j)"),
    ({"spin": np.array([1000, 1100], complex)}, "spin", "complex value (1000+0j)"),
    ({"spin": np.complex128(1000)}, "spin", "complex"),
    ({"spin": [1000, 2j]}, "spin", "complex value 2j"),
    ({"spin": 1000, "tilt": np.array([0.01 + 0.5j])}, "tilt", "complex"),
    ({"spin": 1000, "values": {"top.mass": np.array([0.0515 + 0j])}}, "top.mass", "complex"),
    ({"spin": np.array([1000, np.nan])}, "spin", "finite"),
    ({"spin": [1000, np.inf]}, "spin", "finite"),
    ({"spin": 1000, "offset": [0.0, -np.inf]}, "offset", "finite"),
])
def test_simulate_many_refuses_complex_and_non_finite(study, kwargs, name, says):
    text = _refused(lambda: study.simulate_many(t_end=0.01, **kwargs))
    assert text.startswith(name) and says in text, text


@pytest.mark.parametrize("spin", [1000 + 1j, np.complex128(1000), np.array(1000 + 0j), np.nan, np.inf])
def test_simulate_refuses_complex_and_non_finite(study, spin):
    assert "spin" in _refused(lambda: study.simulate(spin, t_end=0.01))


def test_scan_refuses_complex_spins(study):
    assert "complex" in _refused(lambda: study.scan(np.array([1000 + 1j]), "tilt", [0.01]))


def test_real_arrays_still_run(study):
    r = study.simulate_many(np.array([1000.0, 1100.0]), t_end=0.01)
    assert list(r.status) == ["completed", "completed"]
