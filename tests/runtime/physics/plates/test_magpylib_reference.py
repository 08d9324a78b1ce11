"""Every plate kind's exact field against magpylib, an independent, well-kept implementation of the
fields of magnets and currents (M. Ortner and L. G. Coliado Bandeira, SoftwareX 11, 100466 (2020)).

magpylib >= 5 works in SI (positions in m, magnetization in A/m, polarization J = mu0 M in T,
currents in A, B in T); version 4 used mm and mT. The test extra pins 6.3.0 (pyproject.toml), whose
docstrings say "SI units are used for all inputs and outputs". Its mu0 is CODATA 2022
(1.25663706127e-6), ours CODATA 2018 (scene/constants.py, 1.25663706212e-6): the two differ by
6.8e-10 relative, and B of a given M or I is proportional to mu0, so magpylib's B is scaled by
MU0 / magpylib.mu_0 before the comparison (otherwise every point would differ by that constant).

What is compared (the plate's top face in z = 0, its axis the z axis, docs/contract.md):
- runtime/physics/plates (the exact fields `levitron field` and the expansion's error measure use)
  against magpylib's Cuboid, Cylinder, CylinderSegment, Circle, Polyline and Collection (the square
  with a hole: a Cuboid and a Cylinder of the opposite magnetisation; a compound with a rectangle
  part and a part of sign -1), at points
  on the axis, off the axis near the plate, beside and inside the magnets, and far away;
- the on-axis potential Phi_1..Phi_3 of each kind's sympy builder (what the reduced model, the
  equilibria and the stability analysis use; B_z = -Phi_1 on the axis) against magpylib's B_z and
  its z-derivatives by a five-point finite difference (magpylib gives no gradient);
- the rectangle's exact 3-D field and its gradient in the full model (derive/plate_fields/
  rectangle.py field3d, differentiated by sympy as the generated code is) against magpylib's B and
  a five-point finite difference of it.

Tolerances, and why. Near the plate both give B to a few ulps: |dB| <= 1e-13 |B|. Far away
magpylib's closed forms for magnets and straight segments are differences of terms that are
(d/h)^3 times larger than their result (d the distance from the plate's centre, h its smallest
dimension), and it loses eps (d/h)^3 of relative accuracy (measured: 2e-9 on the axis of a 2 cm
thick block at 10 m, where the 40-digit closed form of `test_far_on_axis_is_ours_that_holds` agrees
with ours to 2e-16); the tolerance grows by that amount for those sources, not for Circle (whose
cel form has no such difference: 2e-14 measured at 100 radii). A five-point difference with step
s has truncation error ~ (s/l)^4 and rounding error ~ 1e-15 l/s relative to |B|/l (l the distance
to the nearest edge); with s = l/2000 both are below 1e-10 (measured), within the tolerance 1e-9 of
the first derivatives. The second derivative's rounding grows as eps (l/s)^2: with s = l/200 it is
measured below 2e-8 of |B|/l^2, the tolerance is 1e-7.
"""
from __future__ import annotations

import math

import magpylib as magpy
import mpmath as mp
import numpy as np
import pytest
import sympy as sp

from levitron.scene import plates
from levitron.scene.constants import MU0
from levitron.derive.plate_fields import build_plate
from levitron.derive.symbols import X, Y, Z
from levitron.runtime.physics.field import exact_field as ef
from levitron.runtime.physics.plates import plate_field

EPS = np.finfo(float).eps
TO_OURS = MU0 / magpy.mu_0          # magpylib's mu0 (CODATA 2022) -> ours (CODATA 2018): module docstring
MOMENT = -0.65                      # A m^2: the thin plates' murho needs a top moment
BR = 0.39                           # T, a ferrite's remanence
MAG = BR / MU0                      # A/m


def resolved(table: dict) -> dict:
    """Scene.params of a [plate] table: plate_<name> -> SI value (scene/plates resolve)."""
    return {f"plate_{k}": float(v) for k, v in plates.resolve(table, MOMENT).items()}


def magpy_b(source, points) -> np.ndarray:
    return np.asarray(source.getB(points), dtype=float).reshape(-1, 3) * TO_OURS


def cuboid(sx, sy, t, m=MAG):
    """A block sx * sy * t, top face in z = 0, magnetised M along +z."""
    return magpy.magnet.Cuboid(dimension=(sx, sy, t), magnetization=(0, 0, m), position=(0, 0, -t / 2))


def cylinder(r, t, m=MAG):
    return magpy.magnet.Cylinder(dimension=(2 * r, t), magnetization=(0, 0, m), position=(0, 0, -t / 2))


def rect_polyline(sx, sy, current):
    """The rim current of a thin rectangular layer, counter-clockwise seen from +z."""
    hx, hy = sx / 2, sy / 2
    return magpy.current.Polyline(current=current, vertices=[(hx, -hy, 0), (hx, hy, 0), (-hx, hy, 0),
                                                             (-hx, -hy, 0), (hx, -hy, 0)])


def thin_current(table: dict) -> float:
    """The dipole density D (A) of a thin plate: its rim current (a uniformly magnetised layer is a
    current loop at its rim, Jackson sec. 5.8), rho = mu0 D / (4 pi)."""
    return ef.dipole_density(resolved(table)["plate_rho"])


DISK = {"kind": "disk", "radius": 0.1, "murho": -0.0026}
ANNULUS = {"kind": "annulus", "radius": 0.1, "hole": 0.03, "murho": -0.0026}
THIN_RECT = {"kind": "rectangle", "side_x": 0.1, "side_y": 0.06, "murho": -0.002}
THIN_HOLED = {**THIN_RECT, "hole": 0.02}     # a thin layer with a hole: its rim loop minus the hole's


class Case:
    """A plate table, its magpylib twin, its size L (the largest length), its smallest dimension h,
    whether magpylib loses eps (d/h)^3 far away (module docstring), and the magnet's extent for the
    points beside and inside it (outer radius or half-sides, inner radius, thickness; None: thin)."""

    def __init__(self, table, source, L, h, far_loss, body=None):
        self.table, self.source, self.L, self.h, self.far_loss, self.body = table, source, L, h, far_loss, body


CASES = {
    "annulus": Case(ANNULUS, magpy.Collection(magpy.current.Circle(diameter=0.2, current=thin_current(ANNULUS)),
                                              magpy.current.Circle(diameter=0.06,
                                                                   current=-thin_current(ANNULUS))),
                    0.1, 0.03, False),
    "disk": Case(DISK, magpy.current.Circle(diameter=0.2, current=thin_current(DISK)), 0.1, 0.1, False),
    "loop": Case({"kind": "loop", "radius": 0.05, "current": 1000.0},
                 magpy.current.Circle(diameter=0.1, current=1000.0), 0.05, 0.05, False),
    "ring_magnet-solid": Case({"kind": "ring_magnet", "r_out": 0.06, "thickness": 0.02, "remanence": BR},
                              cylinder(0.06, 0.02), 0.06, 0.02, True, ("round", 0.06, 0.0, 0.02)),
    "ring_magnet-hollow": Case({"kind": "ring_magnet", "r_out": 0.06, "r_in": 0.02, "thickness": 0.02,
                                "remanence": BR},
                               magpy.magnet.CylinderSegment(dimension=(0.02, 0.06, 0.02, 0, 360),
                                                            magnetization=(0, 0, MAG), position=(0, 0, -0.01)),
                               0.06, 0.02, True, ("round", 0.06, 0.02, 0.02)),
    "rectangle-block": Case({"kind": "rectangle", "side_x": 0.1, "side_y": 0.08, "thickness": 0.02,
                             "remanence": BR},
                            cuboid(0.1, 0.08, 0.02), 0.1, 0.02, True, ("box", (0.05, 0.04), 0.0, 0.02)),
    "rectangle-thin": Case(THIN_RECT, rect_polyline(0.1, 0.06, thin_current(THIN_RECT)), 0.1, 0.06, True),
    "rectangle-holed": Case({"kind": "rectangle", "side": 0.1, "thickness": 0.02, "remanence": BR, "hole": 0.015},
                            magpy.Collection(cuboid(0.1, 0.1, 0.02), cylinder(0.015, 0.02, -MAG)),
                            0.1, 0.02, True, ("box", (0.05, 0.05), 0.0, 0.02)),
    "rectangle-thin-holed": Case(THIN_HOLED, magpy.Collection(
                                     rect_polyline(0.1, 0.06, thin_current(THIN_HOLED)),
                                     magpy.current.Circle(diameter=0.04, current=-thin_current(THIN_HOLED))),
                                 0.1, 0.04, True),
    "compound": Case({"kind": "compound", "parts": [
                          {"kind": "ring_magnet", "r_out": 0.06, "r_in": 0.03, "thickness": 0.02, "remanence": BR},
                          {"kind": "loop", "radius": 0.02, "current": -50.0}]},
                     magpy.Collection(cylinder(0.06, 0.02), cylinder(0.03, 0.02, -MAG),
                                      magpy.current.Circle(diameter=0.04, current=-50.0)),
                     0.06, 0.02, True, ("round", 0.06, 0.03, 0.02)),
    "compound-rectangle": Case({"kind": "compound", "parts": [
                                    {"kind": "rectangle", "side_x": 0.1, "side_y": 0.08, "thickness": 0.02,
                                     "remanence": BR},
                                    {"kind": "ring_magnet", "r_out": 0.015, "thickness": 0.02, "remanence": BR,
                                     "sign": -1},
                                    {"kind": "loop", "radius": 0.02, "current": -50.0}]},
                               magpy.Collection(cuboid(0.1, 0.08, 0.02), cylinder(0.015, 0.02, -MAG),
                                                magpy.current.Circle(diameter=0.04, current=-50.0)),
                               0.1, 0.02, True, ("box", (0.05, 0.04), 0.0, 0.02)),
}


def test_every_kind_has_a_magpylib_reference():
    """A new plate kind must come with its magpylib twin here (expression: on the axis only)."""
    covered = {c.table["kind"] for c in CASES.values()} | {"expression"}
    assert covered == set(plates.KINDS)


def sample_points(case: Case, rng) -> tuple[np.ndarray, np.ndarray]:
    """Points on the axis, near the plate off the axis, beside and inside the magnet, and far
    away (1 to 100 m for a 10 cm plate); returns (points, far) with far the points >= 10 L away."""
    L = case.L
    axis = np.array([[0.0, 0.0, z] for z in L * np.array([0.02, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0])])
    near = np.column_stack([rng.uniform(-1.5, 1.5, (40, 2)) * L, rng.uniform(0.02, 1.5, 40) * L])
    direction = rng.normal(size=(30, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    far = direction * L * np.exp(rng.uniform(math.log(10.0), math.log(1000.0), (30, 1)))
    groups = [axis, near, far]
    if case.body is not None:
        shape, outer, inner, t = case.body
        z = -t * rng.uniform(0.1, 0.9, 20)
        if shape == "round":
            ang = rng.uniform(0, 2 * math.pi, 20)
            beside = rng.uniform(1.1, 2.0, 20) * outer
            within = rng.uniform(inner + 0.1 * (outer - inner), outer - 0.1 * (outer - inner), 20)
            groups += [np.column_stack([beside * np.cos(ang), beside * np.sin(ang), z]),
                       np.column_stack([within * np.cos(ang), within * np.sin(ang), z])]
        else:
            hx, hy = outer
            groups += [np.column_stack([rng.choice([-1, 1], 20) * hx * rng.uniform(1.1, 2, 20),
                                        rng.uniform(-hy, hy, 20), z]),
                       np.column_stack([rng.uniform(-0.9, 0.9, 20) * hx, rng.uniform(-0.9, 0.9, 20) * hy, z])]
    pts = np.vstack(groups)
    return pts, np.linalg.norm(pts, axis=1) >= 10 * L


def tolerance(case: Case, points: np.ndarray) -> np.ndarray:
    """Relative tolerance at each point (module docstring): 1e-13, plus eps (d/h)^3 where magpylib's
    closed form differences large terms."""
    d = np.linalg.norm(points, axis=1)
    return 1e-13 + (EPS * (d / case.h) ** 3 if case.far_loss else 0.0 * d)


@pytest.mark.parametrize("name", list(CASES))
def test_exact_field_against_magpylib(name):
    case = CASES[name]
    pts, far = sample_points(case, np.random.default_rng(30))
    ours = plate_field(case.table, resolved(case.table), pts)
    ref = magpy_b(case.source, pts)
    rel = np.linalg.norm(ours - ref, axis=1) / np.linalg.norm(ref, axis=1)
    tol = tolerance(case, pts)
    worst = int(np.argmax(rel / tol))
    assert np.all(rel <= tol), f"{name}: {rel[worst]:.2e} > {tol[worst]:.2e} at {pts[worst]}"
    assert np.any(far) and np.any(~far)


def test_far_on_axis_is_ours_that_holds():
    """Where the two differ most (far on the axis of a block and of a cylinder), ours agrees with
    the closed on-axis forms at 40 digits to 4 ulps and magpylib's error is the eps (d/h)^3 the
    tolerance allows for: so the looser far tolerance covers magpylib's digits, not ours."""
    mp.mp.dps = 40
    hx, hy, t, R = mp.mpf("0.05"), mp.mpf("0.04"), mp.mpf("0.02"), mp.mpf("0.06")
    omega = lambda w: 4 * mp.atan(hx * hy / (w * mp.sqrt(hx**2 + hy**2 + w**2)))
    k = mp.mpf(MU0) * mp.mpf(MAG)
    for z in (1.0, 10.0):
        zm = mp.mpf(z)
        p = np.array([[0.0, 0.0, z]])
        block = k / (4 * mp.pi) * (omega(zm) - omega(zm + t))
        cyl = k / 2 * ((zm + t) / mp.sqrt((zm + t) ** 2 + R**2) - zm / mp.sqrt(zm**2 + R**2))
        for want, ours, theirs in (
                (block, ef.block_field(p, 0.1, 0.08, 0.02, MAG)[0, 2], magpy_b(cuboid(0.1, 0.08, 0.02), p)[0, 2]),
                (cyl, ef.ring_magnet_field(p, 0.06, 0.0, 0.02, MAG)[0, 2], magpy_b(cylinder(0.06, 0.02), p)[0, 2])):
            assert abs(ours / float(want) - 1) <= 4 * EPS
            assert abs(theirs / float(want) - 1) <= EPS * (z / 0.02) ** 3


def five_point(f, x: np.ndarray, step: float, axis: int, second: bool = False) -> np.ndarray:
    """d f / d x_axis (or d^2 f / d x_axis^2) by the five-point stencil, error O(step^4)."""
    e = np.zeros(3)
    e[axis] = step
    fm2, fm1, fp1, fp2 = (f(x + k * e) for k in (-2, -1, 1, 2))
    if second:
        return (-fm2 + 16 * fm1 - 30 * f(x) + 16 * fp1 - fp2) / (12 * step**2)
    return (fm2 - 8 * fm1 + 8 * fp1 - fp2) / (12 * step)


def onaxis_phis(table: dict, params: dict, kmax: int = 3):
    """Phi_0..Phi_kmax of the kind's sympy builder (the model's on-axis potential), as numpy functions."""
    plate = build_plate(table)
    sub = {s: params[s.name] for s in plate.symbols}
    return [sp.lambdify(Z, d.xreplace(sub), "numpy") for d in plate.phi_derivs(kmax)]


EXPRESSION = {"kind": "expression", "phi0": "b*(1 - z/sqrt(z**2 + c**2))", "params": {"b": 0.0, "c": 0.04}}


def onaxis_cases():
    """(table, params, magpylib source, size) of every kind for the on-axis test; the expression
    plate's formula is the potential of a current loop (Jackson eq. 5.40): b = mu0 I / 2, c = a."""
    out = {name: (c.table, resolved(c.table), c.source, c.L) for name, c in CASES.items()}
    current = 700.0
    params = {"plate_b": MU0 * current / 2, "plate_c": 0.04}
    out["expression"] = (EXPRESSION, params, magpy.current.Circle(diameter=0.08, current=current), 0.04)
    return out


ONAXIS = onaxis_cases()


@pytest.mark.parametrize("name", list(ONAXIS))
def test_onaxis_potential_and_its_derivatives_against_magpylib(name):
    """B_z = -Phi_1, dB_z/dz = -Phi_2, d^2 B_z/dz^2 = -Phi_3 on the axis (B = -grad phi, thesis eq.
    2.2.7), from 0.05 L to 5 L above the plate; the derivatives by a five-point difference of
    magpylib's B_z with step z/2000 (the second derivative z/200: its rounding error grows as
    (z/s)^2; measured 2e-8 at most, module docstring)."""
    table, params, source, L = ONAXIS[name]
    phis = onaxis_phis(table, params)
    bz = lambda p: magpy_b(source, p)[:, 2]
    for z in L * np.array([0.05, 0.3, 1.0, 5.0]):
        x = np.array([[0.0, 0.0, z]])
        ref = [bz(x)[0], five_point(bz, x, z / 2000, 2)[0], five_point(bz, x, z / 200, 2, second=True)[0]]
        scale = abs(ref[0])
        tol = tolerance(CASES[name], x)[0] if name in CASES else 1e-13
        assert -float(phis[1](z)) == pytest.approx(ref[0], rel=tol, abs=tol * scale)
        assert -float(phis[2](z)) == pytest.approx(ref[1], rel=1e-9, abs=1e-9 * scale / z)
        assert -float(phis[3](z)) == pytest.approx(ref[2], rel=1e-7, abs=1e-7 * scale / z**2)


def test_expression_plate_has_no_exact_field_off_the_axis():
    """The expression plate defines its field by the on-axis formula (compared above): it has no
    closed form off the axis, and plate_field says so (None) instead of inventing one."""
    assert plate_field(EXPRESSION, ONAXIS["expression"][1], np.array([[0.01, 0.0, 0.05]])) is None


@pytest.mark.parametrize("table", [CASES["rectangle-block"].table, THIN_RECT], ids=["block", "thin"])
def test_rectangle_model_field_and_gradient_against_magpylib(table):
    """The full model's field of a rectangle is its exact 3-D field (field3d), and its force and
    torque use dB_i/dx_j, which derive gets by differentiating field3d with sympy: both against
    magpylib (B, and a five-point difference of B for the gradient), off the axis near the plate
    (1 cm to 15 cm away from its edges) and on the axis."""
    params = resolved(table)
    plate = build_plate(table)
    sub = {s: params[s.name] for s in plate.symbols}
    B = sp.Matrix(plate.field3d(X, Y, Z)).xreplace(sub)
    field = sp.lambdify((X, Y, Z), B, "numpy")
    grad = sp.lambdify((X, Y, Z), B.jacobian([X, Y, Z]), "numpy")
    source = CASES["rectangle-block"].source if table is not THIN_RECT else CASES["rectangle-thin"].source
    rng = np.random.default_rng(5)
    pts = np.vstack([[[0.0, 0.0, 0.032], [0.0, 0.0, 0.1]],
                     np.column_stack([rng.uniform(-0.08, 0.08, (12, 2)), rng.uniform(0.01, 0.15, 12)])])
    for p in pts:
        x = p[None, :]
        ref_b = magpy_b(source, x)[0]
        scale = np.linalg.norm(ref_b)
        assert np.linalg.norm(np.asarray(field(*p), dtype=float).ravel() - ref_b) <= 1e-13 * scale
        step = p[2] / 2000                # the nearest edge is at least z away
        ref_g = np.column_stack([five_point(lambda q: magpy_b(source, q), x, step, j)[0] for j in range(3)])
        ours_g = np.asarray(grad(*p), dtype=float)
        assert np.max(np.abs(ours_g - ref_g)) <= 1e-9 * scale / p[2]
