"""What derive emits for a scene: the parts its `model.needs` lists, and their functions.

"Model only what a scene needs": a scene that asks for the reduced model gets the 4-D functions
(thesis eq. 3.2.12) and the on-axis potential, never the 12-D ones.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from levitron.scene.checks import SceneError

from . import field as fieldmod
from . import friction as frictionmod
from .invariants import angular_momenta
from .geometry import Plate
from .mechanics import hamiltonian_system
from .reduction import reduced_system
from .symbols import PHYSICAL, TILT, Phi, X, Y, Z, abstract_field, moment_offset, moment_tilt


@dataclass(frozen=True)
class Function:
    """One generated function: out = f(in, p), all symbolic (Phi(k, z) still abstract)."""

    name: str
    inputs: tuple           # the symbols of `in`, in order
    outputs: tuple          # sympy expressions, flattened row-major
    shape: tuple            # shape of the output (for documentation)
    doc: str


@dataclass
class ModelSpec:
    scene: str
    plate: Plate
    order: int
    coordinates: str
    params: tuple                       # parameter symbols in vector order
    parts: dict = field(default_factory=dict)   # part name -> {"states": [...], "functions": [...]}
    field3d: sp.Matrix | None = None            # exact B(x, y, z) of a non-axisymmetric plate
    functions: list = field(default_factory=list)

    @property
    def kmax(self) -> int:
        """Highest Phi_k the on-axis function returns: order + 2 (>= 4 for the stability analysis)."""
        return self.order + 2


def _part_functions(prefix: str, state, rhs: sp.Matrix, H: sp.Expr, with_jac: bool, what: str):
    funcs = [
        Function(f"{prefix}_rhs", tuple(state), tuple(rhs), (len(state),),
                 f"{what}: Hamilton's equations d(state)/dt"),
        Function(f"{prefix}_energy", tuple(state), (H,), (1,), f"{what}: the Hamiltonian (energy)"),
    ]
    if with_jac:
        J = rhs.jacobian(sp.Matrix(state))
        funcs.append(Function(f"{prefix}_jac", tuple(state), tuple(J), J.shape,
                              f"{what}: Jacobian d rhs / d state, row-major"))
    return funcs


def build_spec(scene_name: str, plate: Plate, order: int, coordinates: str, needs,
               friction: bool = False, tilted: bool = False, offset: bool = False,
               askew: bool = False) -> ModelSpec:
    """The functions of a scene. With `friction`, the full model's momentum rows carry the
    generalised forces of air friction (derive/friction.py), its rates k_spin, k_tilt, k_trans
    close the parameter vector and `full_dissipation` (2F = -dH/dt) is emitted; without it the
    model is the conservative one of thesis 2.3. With `tilted` (a base tilt, plate.tilt) gravity in
    the full model is along a tilted vector (derive/mechanics.py) and base_tilt, base_tilt_azimuth
    close the parameter vector; the reduced model does not exist then (scene/load.py refuses it).
    With `offset` (top.moment_offset) the full model's moment sits at r + d n, and moment_offset
    comes after the tilt's; scene/load.py gives such a scene no reduced model either (it is not
    derived). With `askew` (top.moment_tilt) the moment is tilted from the axis in the body
    (derive/mechanics.py) and moment_tilt comes last; no reduced model (the spin is not conserved)."""
    rates = tuple(frictionmod.RATES) if friction else ()
    spec = ModelSpec(scene_name, plate, order, coordinates,
                     tuple(PHYSICAL) + tuple(plate.symbols) + rates + (TILT if tilted else ())
                     + ((moment_offset,) if offset else ()) + ((moment_tilt,) if askew else ()))
    if (tilted or offset or askew) and "reduced" in needs:
        raise ValueError("a tilted base or an offset magnet has no reduced model here")
    if "reduced" in needs:
        red = reduced_system(order)
        spec.parts["reduced"] = {"states": red.state_names, "equations": "thesis eq. 3.2.12"}
        spec.functions += _part_functions("reduced", red.state, red.rhs, red.H, True,
                                          "reduced model on the invariant set (thesis 3.2.12)")
    B3 = None
    if offset and not plate.axisymmetric:
        raise SceneError(f"top.moment_offset is modelled over axisymmetric plates only, not this "
                         f"{plate.kind} plate: remove it")
    if not plate.axisymmetric:
        spec.field3d = plate.model_field(order, X, Y, Z)
        B3 = sp.ImmutableMatrix(abstract_field())
    if "full" in needs:
        full = hamiltonian_system(coordinates, order, B3, tilted, offset, askew)
        what = f"full 12-D model, {coordinates} angles (thesis 2.3)"
        if tilted:
            what += " on a tilted base (gravity along a tilted vector, derive/mechanics.py)"
        if offset:
            what += ", the magnet's centre off the centre of mass along the axis"
        if askew:
            what += ", the moment tilted from the axis in the body"
        equations = "thesis eqs. 2.3.9-2.3.16 (" + coordinates + ")"
        rhs = full.rhs
        if friction:
            rhs = frictionmod.dissipative_rhs(full)
            what += " with air friction (Rayleigh dissipation, derive/friction.py)"
            equations += " + generalised forces of air friction"
        spec.parts["full"] = {"states": full.state_names, "equations": equations}
        spec.functions += _part_functions("full", full.state, rhs, full.H, "linear" in needs, what)
        spec.functions.append(Function(
            "full_axis", tuple(full.state), tuple(full.rotation.n), (3,),
            "the symmetry axis n = R_bs e_z in space components (derive/kinematics.py)"))
        spec.functions.append(Function(
            "full_invariants", tuple(full.state), angular_momenta(full), (2,),
            "the angular momenta L_z (conserved by the axisymmetric field) and L.n (by any field), "
            "derive/invariants.py"))
        if friction:
            spec.functions.append(Function(
                "full_dissipation", tuple(full.state), (frictionmod.dissipated_power(full),), (1,),
                f"{what}: the dissipated power 2F = -dH/dt"))
    spec.functions.append(Function(
        "onaxis", (Z,), tuple(Phi(k, Z) for k in range(spec.kmax + 1)), (spec.kmax + 1,),
        "on-axis potential and its derivatives Phi_0..Phi_K (thesis eq. 2.2.6)"))
    if B3 is None:
        B, what = fieldmod.field(order), f"expansion to order {order} (thesis eq. 2.2.7)"
    else:
        B, what = B3, f"exact 3-D field of the {plate.kind} plate (no expansion)"
        if plate.axial is not None:
            what = (f"exact 3-D field of the {plate.kind} plate's non-axisymmetric parts, its "
                    f"axisymmetric parts' expansion to order {order} (thesis eq. 2.2.7)")
    spec.functions.append(Function("field", (X, Y, Z), tuple(B), (3,), f"B = -grad(phi), {what}"))
    return spec
