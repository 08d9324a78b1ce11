"""runtime/physics/routes/eigen_route.balancing is LAPACK's dgebal (job 'S'), the scaling
scipy.linalg.matrix_balance(permute=False) returns: the same powers of 2 on every scene's generated
Jacobian, at spins inside and outside its interval, and on random matrices whose entries span
twenty decades."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from levitron.scene.load import load_scene
from levitron.runtime.model.load import load_model
from levitron.runtime.physics.routes import eigen_route
from levitron.runtime.physics.routes.eigen_route import balancing
from levitron.runtime.physics.stability.analysis import stability_of

SCENES = ("thesis", "thesis_stable", "ring_magnet", "loop", "square", "thesis_air")


def scipy_balancing(J):
    return scipy.linalg.matrix_balance(J, permute=False, separate=True)[1][0]


@pytest.mark.parametrize("scene", SCENES)
def test_the_scaling_of_every_matrix_the_eigen_route_solves_is_lapacks(scene, monkeypatch):
    """Every matrix `levitron stability`'s eigen route solves (its spin grid and bisections,
    hundreds per scene; it balances once and reuses the scaling), recorded and compared."""
    seen = []
    check = eigen_route.on_imaginary_axis
    monkeypatch.setattr(eigen_route, "on_imaginary_axis", lambda J, d=None: seen.append(J.copy()) or check(J, d))
    stability_of(load_model(load_scene(scene)))
    assert len(seen) > 50
    for J in seen:
        assert np.array_equal(balancing(J), scipy_balancing(J)), (scene, J)


def test_the_scaling_of_random_matrices_is_lapacks():
    rng = np.random.default_rng(7)
    for n in (2, 4, 6, 12):
        for _ in range(300):
            J = rng.standard_normal((n, n)) * 10.0 ** rng.uniform(-10, 10, (n, n))
            J[rng.random((n, n)) < 0.3] = 0.0
            assert np.array_equal(balancing(J), scipy_balancing(J)), J


def test_a_nan_is_refused():
    with pytest.raises(ValueError, match="NaN"):
        balancing(np.array([[1.0, np.nan], [0.5, 2.0]]))
