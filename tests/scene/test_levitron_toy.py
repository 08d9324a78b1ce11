"""scenes/levitron_toy.toml's stand-ins hold what its comment says (docs/levitron_toy.md).

- The remanence is the one that puts the hover height at the measured 3.2 cm: B is linear in the
  magnetisation, so m g + mu Phi_2(z; M) = 0 (thesis eq. 3.3.2) is solved in closed form here, a
  second route beside `levitron optimize --fit-height` (a CasADi Newton rootfinder).
- The hole's radius: only for holes of about 3.5-6 mm (each with its remanence refitted) is 3.2 cm
  inside the stable band; at 3 mm it lies above the band, at 6.5 mm below.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from levitron.scene import plates
from levitron.derive.plate_fields import build_plate
from levitron.scene.plates.symmetry import symmetry
from levitron.scene.load import load_scene
from levitron.derive.symbols import Z
from levitron.runtime.physics.equilibrium import finder as eqm

Z_MEASURED = 0.032      # m, Simon et al.'s hover height


def onaxis(table: dict, mu: float, kmax: int = 6):
    """z -> [Phi_0..Phi_kmax] of the plate's sympy builder, and the plate's length scale."""
    plate = build_plate(table)
    p = {f"plate_{k}": float(v) for k, v in plates.resolve(table, mu).items()}
    fs = [sp.lambdify(Z, d.xreplace({s: p[s.name] for s in plate.symbols}), "math")
          for d in plate.phi_derivs(kmax)]
    return (lambda z: np.array([f(z) for f in fs])), plates.length_scale(table, p)


def fitted_remanence(table: dict, m: float, g: float, mu: float) -> float:
    """The remanence that makes m g + mu Phi_2(Z_MEASURED) = 0 (Phi is linear in it)."""
    on, _ = onaxis(table, mu)
    return table["remanence"] * (-m * g / (mu * on(Z_MEASURED)[2]))


@pytest.fixture(scope="module")
def toy():
    return load_scene("levitron_toy")


def test_the_remanence_puts_the_hover_height_at_the_measured_3_2_cm(toy):
    top, plate = toy.data["top"], toy.data["plate"]
    br = fitted_remanence(plate, top["mass"], toy.data["g"], top["moment"])
    assert br == pytest.approx(plate["remanence"], rel=1e-6)
    on, scale = onaxis(plate, top["moment"])
    rep = eqm.analyse(on, top["mass"], toy.data["g"], top["A"], top["C"], top["moment"], scale)
    assert [round(e.z, 6) for e in rep.stable] == [Z_MEASURED]
    band = rep.stable_band
    assert band.z[0] < Z_MEASURED < band.z[1] and band.mass[0] < top["mass"] < band.mass[1]


@pytest.mark.parametrize("hole,where", [(0.003, "above"), (0.0035, "inside"), (0.005, "inside"),
                                        (0.006, "inside"), (0.0065, "below")])
def test_only_a_small_hole_makes_3_2_cm_a_stable_hover(toy, hole, where):
    top = toy.data["top"]
    plate = {**toy.data["plate"], "hole": hole}
    plate["remanence"] = fitted_remanence(plate, top["mass"], toy.data["g"], top["moment"])
    on, scale = onaxis(plate, top["moment"])
    band = eqm.analyse(on, top["mass"], toy.data["g"], top["A"], top["C"], top["moment"], scale).stable_band
    got = "below" if Z_MEASURED < band.z[0] else "above" if Z_MEASURED > band.z[1] else "inside"
    assert got == where, (hole, band.z)


def test_the_toy_is_four_fold_and_states_its_reference(toy):
    assert symmetry(toy.data["plate"], toy.params).name == "four-fold"
    ref = toy.data["reference"]
    assert ref["z_stable"] == Z_MEASURED and ref["spin_interval"] == [114.0, 254.0]
