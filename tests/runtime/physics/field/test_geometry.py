"""Base-plate geometries: on-axis fields against independent formulas, the expansion's
convergence to the exact field, the rectangle's 3-D field, the generated code, scenes and the
`field` command. Thesis eqs. 2.2.6-2.2.11; exact fields in runtime/physics/field/exact_field.py."""
from __future__ import annotations

import json
import math
import shutil

import mpmath as mp
import numpy as np
import pytest
import sympy as sp
from scipy import integrate

from levitron.derive import field_order as fo
from levitron.scene.plates import length_scale
from levitron.derive.plate_fields import build_plate
from levitron.scene.constants import MU0
from levitron.scene.load import SceneError, load_scene, validate
from levitron.derive.symbols import Z
from levitron.runtime.physics.field import exact_field as ef
from levitron.runtime.physics.plates import plate_field

RNG = np.random.default_rng(7)
ZS = np.array([0.004, 0.02, 0.05, 0.1, 0.3, 2.0])


def numeric(table: dict, values: dict, kmax: int = 5):
    """Phi_0..Phi_kmax of a plate as float functions of z (parameters substituted)."""
    plate = build_plate(table)
    sub = {s: values[s.name] for s in plate.symbols}
    return plate, [sp.lambdify(Z, d.xreplace(sub), "math") for d in plate.phi_derivs(kmax)]


def bz_axis(phis, z):
    return -phis[1](z)   # B = -grad(phi): on the axis B_z = -Phi_1 (thesis eq. 2.2.7)


# ---------------------------------------------------------------- on the axis, independent forms

def test_annulus_on_axis_dipole_layer():
    a, w, D = 0.1, 0.03, 2000.0
    _, ph = numeric({"kind": "annulus"}, {"plate_a": a, "plate_w": w, "plate_rho": MU0 * D / (4 * math.pi)})
    for z in ZS:
        want = MU0 * D / 2 * (a**2 / (z**2 + a**2) ** 1.5 - w**2 / (z**2 + w**2) ** 1.5)
        assert bz_axis(ph, z) == pytest.approx(want, rel=1e-13)


def test_loop_on_axis_closed_form():
    a, cur = 0.05, 800.0
    _, ph = numeric({"kind": "loop"}, {"plate_a": a, "plate_current": cur})
    for z in ZS:
        assert bz_axis(ph, z) == pytest.approx(MU0 * cur * a**2 / (2 * (a**2 + z**2) ** 1.5), rel=1e-14)


@pytest.mark.parametrize("r_in", [0.0, 0.02])
def test_ring_magnet_on_axis_closed_form(r_in):
    R, t, M = 0.06, 0.02, 3.1e5

    def cyl(z, rad):
        return MU0 * M / 2 * ((z + t) / math.hypot(z + t, rad) - z / math.hypot(z, rad))

    _, ph = numeric({"kind": "ring_magnet", "r_in": r_in},
                    {"plate_r_out": R, "plate_r_in": r_in, "plate_thickness": t, "plate_magnetization": M})
    for z in ZS[:5]:     # the reference itself cancels far away
        want = cyl(z, R) - (cyl(z, r_in) if r_in else 0.0)
        assert bz_axis(ph, z) == pytest.approx(want, rel=1e-12)


def test_rectangle_on_axis_against_quadrature_and_exact():
    sx, sy, t, M = 0.1, 0.08, 0.02, 3e5
    _, ph = numeric({"kind": "rectangle", "thickness": t},
                    {"plate_side_x": sx, "plate_side_y": sy, "plate_thickness": t, "plate_magnetization": M})
    for z in (0.01, 0.05, 0.3):
        exact = ef.block_field([[0, 0, z]], sx, sy, t, M)[0, 2]
        assert bz_axis(ph, z) == pytest.approx(exact, rel=1e-13)
    # surface-charge quadrature: +M on z = 0, -M on z = -t (Furlani 2001)
    z = 0.04
    hz = sum(s * integrate.dblquad(lambda y, x: (z - z0) / (x * x + y * y + (z - z0) ** 2) ** 1.5,
                                   -sx / 2, sx / 2, -sy / 2, sy / 2, epsabs=0, epsrel=1e-12)[0]
             for z0, s in ((0.0, 1.0), (-t, -1.0)))
    assert bz_axis(ph, z) == pytest.approx(MU0 * M * hz / (4 * math.pi), rel=1e-10)
    # Phi_0 is the potential: -dPhi0/dz = B_z (finite difference)
    h = 1e-6
    assert -(ph[0](z + h) - ph[0](z - h)) / (2 * h) == pytest.approx(bz_axis(ph, z), rel=1e-7)


def test_thin_square_on_axis_is_rectangular_loop():
    s, rho = 0.12, 0.002
    _, ph = numeric({"kind": "rectangle", "thickness": 0.0},
                    {"plate_side_x": s, "plate_side_y": s, "plate_rho": rho})
    for z in (0.01, 0.07, 1.0):
        want = ef.rect_loop_field([[0, 0, z]], s, s, 4 * math.pi * rho / MU0)[0, 2]
        assert bz_axis(ph, z) == pytest.approx(want, rel=1e-13)


def test_expression_plate_phi0_and_bz():
    _, ph = numeric({"kind": "expression", "phi0": "b*(1 - z/sqrt(z**2 + c**2))",
                     "params": {"b": 1.0, "c": 1.0}}, {"plate_b": 0.3, "plate_c": 0.05})
    _, disk = numeric({"kind": "disk"}, {"plate_a": 0.05, "plate_rho": 0.3 / (2 * math.pi)})
    _, viabz = numeric({"kind": "expression", "bz": "b*c**2/(z**2 + c**2)**(3/2)",
                        "params": {"b": 1.0, "c": 1.0}}, {"plate_b": 0.3, "plate_c": 0.05})
    for z in (0.01, 0.1, 1.0):
        for k in range(1, 5):
            assert ph[k](z) == pytest.approx(disk[k](z), rel=1e-12)
            assert viabz[k](z) == pytest.approx(disk[k](z), rel=1e-12)


def test_expression_plate_refuses_bad_formula():
    with pytest.raises(SceneError, match=r"plate\.phi0.*__import__"):
        build_plate({"kind": "expression", "phi0": "__import__('os')", "params": {}})


def test_compound_is_the_sum_of_its_parts():
    table = {"kind": "compound", "parts": [{"kind": "disk"}, {"kind": "loop"}]}
    vals = {"plate_p0_a": 0.1, "plate_p0_rho": 0.001, "plate_p1_a": 0.03, "plate_p1_current": -50.0}
    _, ph = numeric(table, vals)
    _, d = numeric({"kind": "disk"}, {"plate_a": 0.1, "plate_rho": 0.001})
    _, lo = numeric({"kind": "loop"}, {"plate_a": 0.03, "plate_current": -50.0})
    for z in (0.01, 0.1):
        for k in range(5):
            assert ph[k](z) == pytest.approx(d[k](z) + lo[k](z), rel=1e-13)
    pts = [[0.01, 0.02, 0.05]]
    B = plate_field(table, vals, pts)
    assert np.allclose(B, ef.annulus_field(pts, 0.1, 0, 4 * math.pi * 0.001 / MU0)
                       + ef.loop_field(pts, 0.03, -50.0), rtol=1e-14)


# ---------------------------------------------------------------- off the axis

CASES = {
    "loop": ({"kind": "loop"}, {"plate_a": 0.05, "plate_current": 800.0},
             lambda p: ef.loop_field(p, 0.05, 800.0)),
    "annulus": ({"kind": "annulus"}, {"plate_a": 0.1, "plate_w": 0.03, "plate_rho": 0.0026},
                lambda p: ef.annulus_field(p, 0.1, 0.03, 4 * math.pi * 0.0026 / MU0)),
    "ring_magnet": ({"kind": "ring_magnet", "r_in": 0.03},
                    {"plate_r_out": 0.06, "plate_r_in": 0.03, "plate_thickness": 0.02,
                     "plate_magnetization": 3.1e5},
                    lambda p: ef.ring_magnet_field(p, 0.06, 0.03, 0.02, 3.1e5)),
}


@pytest.mark.parametrize("name", list(CASES))
def test_whittaker_integral_is_the_exact_field(name):
    """derive/field_order.py's exact field (from Phi_1 alone) against runtime/physics/field/exact_field.py."""
    table, vals, exact = CASES[name]
    _, ph = numeric(table, vals, 1)
    phi1 = sp.lambdify(Z, build_plate(table).phi_derivs(1)[1].xreplace(
        {s: vals[s.name] for s in build_plate(table).symbols}), "numpy")
    r = RNG.uniform(0, 0.08, 12)
    z = RNG.uniform(0.01, 0.15, 12)
    br, bz = fo.whittaker_field(phi1, r, z)
    B = exact(np.stack([r, 0 * r, z], axis=1))
    scale = np.abs(B).max()
    assert np.allclose(br, B[:, 0], rtol=0, atol=1e-12 * scale)
    assert np.allclose(bz, B[:, 2], rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("name", list(CASES))
def test_expansion_converges_to_exact_field(name):
    """Thesis eq. 2.2.6 to order 2, 4, ..., 12 at radii 0.1, 0.2, 0.3 of the plate's size: the error
    against the exact (elliptic-integral) field falls with the order at every radius."""
    table, vals, exact = CASES[name]
    plate = build_plate(table)
    size = length_scale(table, vals)
    sub = {s: vals[s.name] for s in plate.symbols}
    phis = [sp.lambdify(Z, d.xreplace(sub), "numpy") for d in plate.phi_derivs(13)]
    z = np.linspace(0.6 * size, 1.5 * size, 7)
    for frac in (0.1, 0.2, 0.3):
        r = np.full_like(z, frac * size)
        B = exact(np.stack([r, 0 * r, z], axis=1))
        scale = np.abs(B).max()
        errs = []
        for order in (2, 4, 6, 8, 10, 12):
            br, bz = fo.expansion_field(phis, order, r, z)
            errs.append(max(np.abs(br - B[:, 0]).max(), np.abs(bz - B[:, 2]).max()) / scale)
        print(name, frac, ["%.1e" % e for e in errs])
        assert all(e2 < e1 for e1, e2 in zip(errs, errs[1:]) if e1 > 1e-13), errs
        assert errs[-1] < errs[0] * 1e-3


def test_choose_order_is_the_lowest_that_meets_the_tolerance():
    scene = load_scene("thesis")
    order, err = fo.choose_order(scene, 1e-3, 0.02)
    assert err <= 1e-3
    plate = build_plate({"kind": "annulus"})
    zr = fo.default_heights(scene, fo._numeric_phis(plate, scene.params, 2))
    assert zr[0] < 0.0762 < 0.1568 < zr[1]          # both thesis equilibria inside (thesis 3.3)
    errors = fo.order_errors(plate, scene.params, 0.02, zr)
    assert errors[order] == err
    assert all(errors[o] > 1e-3 for o in errors if o < order)
    with pytest.raises(SceneError, match="field.tolerance"):
        fo.choose_order(scene, 1e-14, 0.09)


# ---------------------------------------------------------------- the rectangle's 3-D field

x, y = sp.symbols("x y", real=True)


@pytest.fixture(scope="module")
def block():
    vals = {"plate_side_x": 0.1, "plate_side_y": 0.07, "plate_thickness": 0.02, "plate_magnetization": 3e5}
    plate = build_plate({"kind": "rectangle", "thickness": 0.02})
    sub = {s: vals[s.name] for s in plate.symbols}
    B = plate.field3d(x, y, Z).xreplace(sub)
    return plate, sub, B


def test_rectangle_field3d_against_charge_quadrature(block):
    _, _, B = block
    f = sp.lambdify((x, y, Z), list(B), "numpy")
    for p in ([0.02, 0.01, 0.03], [0.09, -0.05, 0.02]):
        got = np.array(f(*p), dtype=float)
        ref = np.zeros(3)
        for z0, s in ((0.0, 1.0), (-0.02, -1.0)):
            for c in range(3):
                def integrand(yy, xx):
                    r = np.array(p) - np.array([xx, yy, z0])
                    return r[c] / np.linalg.norm(r) ** 3
                ref[c] += s * integrate.dblquad(integrand, -0.05, 0.05, -0.035, 0.035,
                                                epsabs=0, epsrel=1e-11)[0]
        ref *= MU0 * 3e5 / (4 * math.pi)
        assert np.max(np.abs(got - ref)) <= 1e-9 * np.linalg.norm(ref)
        assert np.allclose(got, ef.block_field([p], 0.1, 0.07, 0.02, 3e5)[0], rtol=1e-12, atol=1e-16)


def test_rectangle_field3d_is_divergence_and_curl_free(block):
    """Exact sympy derivatives, evaluated at random points above the plate: div B = curl B = 0."""
    _, _, B = block
    v = (x, y, Z)
    div = sum(sp.diff(B[i], v[i]) for i in range(3))
    curl = [sp.diff(B[2], y) - sp.diff(B[1], Z), sp.diff(B[0], Z) - sp.diff(B[2], x),
            sp.diff(B[1], x) - sp.diff(B[0], y)]
    grad = [sp.diff(B[i], v[j]) for i in range(3) for j in range(3)]
    f = sp.lambdify(v, [div] + curl + grad, "numpy")
    for p in RNG.uniform([-0.1, -0.1, 0.005], [0.1, 0.1, 0.2], (20, 3)):
        vals = np.array(f(*p), dtype=float)
        scale = np.abs(vals[4:]).max()
        assert np.abs(vals[:4]).max() <= 1e-12 * scale


def test_thin_rectangle_field_is_minus_grad_of_solid_angle_potential():
    plate = build_plate({"kind": "rectangle", "thickness": 0.0})
    sub = {s: v for s, v in zip(plate.symbols, (0.1, 0.13, 0.002))}
    B = plate.field3d(x, y, Z).xreplace(sub)
    phi = plate.potential3d(x, y, Z).xreplace(sub)
    grad = [-sp.diff(phi, v) for v in (x, y, Z)]
    f = sp.lambdify((x, y, Z), list(B) + grad, "numpy")
    for p in RNG.uniform([-0.1, -0.1, 0.01], [0.1, 0.1, 0.2], (10, 3)):
        vals = np.array(f(*p), dtype=float)
        assert np.allclose(vals[:3], vals[3:], rtol=1e-11, atol=1e-13 * np.abs(vals).max())
        exact = ef.rect_loop_field([p], 0.1, 0.13, 4 * math.pi * 0.002 / MU0)[0]
        assert np.allclose(vals[:3], exact, rtol=1e-11, atol=1e-13 * np.abs(exact).max())


# ---------------------------------------------------------------- generated code

@pytest.mark.parametrize("ratio", [0.0, 1e-3, 0.3, 0.999])
def test_generated_c_phi_k_precision(derived_model, ratio):
    """Phi_1..Phi_4 from the generated C (`onaxis`) vs 50-digit mpmath, z from 1e-3 a to 1e3 a
    (relative error against |Phi_k| + |z Phi_{k+1}|: see tests/runtime/physics/field/test_onaxis_precision.py)."""
    model = derived_model("reduced_only", f"plate.hole={ratio * 0.1!r}")
    a, w = model.param("plate_a"), model.param("plate_w")
    rho = model.param("plate_rho")
    mp.mp.dps = 50
    zz, A, W = sp.symbols("zz A W", positive=True)
    phi0 = 2 * sp.pi * z_rho * zz * (1 / sp.sqrt(zz**2 + W**2) - 1 / sp.sqrt(zz**2 + A**2))
    ref = [sp.lambdify((zz, A, W, z_rho), sp.diff(phi0, zz, k), "mpmath") for k in range(6)]
    worst = 0.0
    for z in a * np.geomspace(1e-3, 1e3, 37):
        got = model.onaxis(z)
        args = (mp.mpf(z), mp.mpf(a), mp.mpf(w), mp.mpf(rho))
        for k in range(1, 5):
            r0, r1 = ref[k](*args), ref[k + 1](*args)
            worst = max(worst, float(abs(got[k] - r0) / (abs(r0) + abs(z * r1))))
    print(f"w/a = {ratio}: generated C worst {worst:.2e}")
    assert worst <= 1e-12


z_rho = sp.Symbol("z_rho", real=True)


def test_generated_field_matches_exact_near_axis(derived_model):
    model = derived_model("loop", 'model.needs=["reduced"]', "field.order=8")
    scene = model.scene
    pts = np.array([[0.002, 0.001, 0.03], [0.005, -0.004, 0.05], [0.0, 0.0, 0.02]])
    exact = plate_field(scene.data["plate"], scene.params, pts)
    for p, b in zip(pts, exact):
        got = model.field(p)
        assert np.linalg.norm(got - b) <= 1e-6 * np.linalg.norm(b)


def test_reduced_only_scene_has_no_full_model(derived_model):
    model = derived_model("reduced_only")
    files = sorted(p.name for p in model.folder.iterdir())
    assert not any(f.startswith("full_") for f in files), files
    assert "full" not in model.manifest.parts
    assert not any(n.startswith("full_") for n in model.manifest.functions)
    assert "full_" not in (model.folder / "model.c").read_text()
    assert "full_" not in (model.folder / "model.h").read_text()


# ---------------------------------------------------------------- scenes and the command

@pytest.mark.parametrize("name", ["loop", "ring_magnet", "square", "reduced_only"])
def test_scenes_load(name):
    scene = load_scene(name)
    assert scene.params["m"] > 0


BASE = {"top": {"mass": 0.02, "A": 2e-6, "C": 1.3e-6, "moment": -0.5}, "field": {"order": 2}}


@pytest.mark.parametrize("plate,message", [
    ({"kind": "loop", "radius": 0.05}, "current"),
    ({"kind": "loop", "radius": 0.05, "current": 1.0, "center_field": 0.01}, "exactly one"),
    ({"kind": "ring_magnet", "r_out": 0.05, "r_in": 0.06, "thickness": 0.01, "remanence": 0.4}, "plate.r_in"),
    ({"kind": "ring_magnet", "r_out": 0.05, "thickness": 0.01}, "magnetization"),
    ({"kind": "ring_magnet", "r_out": 0.05, "thickness": -0.01, "remanence": 0.4}, "plate.thickness"),
    ({"kind": "rectangle", "side": 0.1, "side_x": 0.1, "remanence": 0.4, "thickness": 0.01}, "side"),
    ({"kind": "rectangle", "side": 0.1, "remanence": 0.4}, "thickness"),
    ({"kind": "expression", "phi0": "z", "bz": "z"}, "exactly one"),
    ({"kind": "expression", "phi0": "z*sqrt", "params": {"sqrt": 1.0}}, "plate.params.sqrt"),
    ({"kind": "compound", "parts": []}, "parts"),
    ({"kind": "compound", "parts": [{"kind": "square", "side": 0.1}]}, "plate.parts[0].kind"),
    ({"kind": "compound", "parts": [{"kind": "rectangle", "side": 0.1}]}, "plate.parts[0]"),
    ({"kind": "compound", "parts": [{"kind": "disk", "radius": 0.1, "murho": 1e-3, "hole": 0.01}]},
     "plate.parts[0]"),
    ({"kind": "loop", "radius": 0.05, "current": 1.0, "bogus": 1}, "bogus"),
])
def test_bad_plate_keys_are_one_line_errors(plate, message):
    data = json.loads(json.dumps(BASE))
    data["plate"] = plate
    data["name"] = "bad"
    with pytest.raises(SceneError) as info:
        validate(data)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_field_command_json(tmp_path, monkeypatch, capsys, seed_cache):
    from levitron.runtime.cli.main import main
    monkeypatch.setenv("LEVITRON_CACHE", str(seed_cache(tmp_path / "cache")))
    scene = tmp_path / "loopx.toml"
    shutil.copy(load_scene("loop").path, scene)
    text = scene.read_text().replace('name = "loop"', 'name = "loopx"')
    scene.write_text(text.replace('needs = ["reduced", "full", "linear"]', 'needs = ["reduced"]'))
    rc = main(["field", str(scene), "--at", "0,0,0.03", "--at", "0.005,0.002,0.04", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and len(out["points"]) == 2
    for pt in out["points"]:
        assert set(pt) >= {"r", "B", "B_exact"}
        assert np.allclose(pt["B"], pt["B_exact"], rtol=2e-3, atol=1e-3 * np.abs(pt["B_exact"]).max())
    assert main(["field", str(scene), "--at", "0,0", "--json"]) == 2


# ---------------------------------------------------------------- square versus disk

def _stability_summary(table, vals, g, A, C, mu, scale, frac=1.1):
    """z_c, largest mass, stable band, and for the top that hovers at frac * z_c its mass and spin
    interval (runtime/physics/equilibrium/finder.py, runtime/physics/stability/analysis.py: exact linear analysis,
    thesis 3.3). On the
    axis a 4-fold symmetric plate's field equals an axisymmetric one's to second order in x, y, so
    the on-axis Phi_k decide equilibria and linear stability exactly."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.physics.stability import analysis as stability
    _, ph = numeric(table, vals, 5)
    onaxis = lambda z: np.array([f(z) for f in ph])
    rep = eqm.analyse(onaxis, 0.01, g, A, C, mu, scale)
    z_s = frac * rep.z_c
    m_s = eqm.hover_mass(onaxis, g, mu, z_s)
    res = stability.analyse(onaxis, m_s, g, A, C, mu, scale, z_s=z_s)
    return {"z_c": rep.z_c, "max_mass": rep.max_mass, "band_z": rep.stable_bands[0].z,
            "band_mass": rep.stable_bands[0].mass, "m_s": m_s, "spin": res.spin_interval}


def test_square_versus_disk_of_the_same_area():
    """Berry (via thesis sec. 2.2): the plate's shape matters little. Thin layers of the thesis's
    strength (disk a = 10 cm vs square of side sqrt(pi) a), and the toy's 10 x 10 x 2 cm ferrite
    base vs a cylinder magnet of the same area and thickness: z_c, the largest mass and the spin
    interval at 1.1 z_c differ by a few per cent."""
    g, A, C = 9.81, 2.2e-6, 1.32e-6
    a, rho = 0.1, 0.0026209383
    side = math.sqrt(math.pi) * a
    pairs = {
        "thin": (({"kind": "disk"}, {"plate_a": a, "plate_rho": rho}),
                 ({"kind": "rectangle", "thickness": 0.0},
                  {"plate_side_x": side, "plate_side_y": side, "plate_rho": rho}), -1.0, a),
        "block": (({"kind": "ring_magnet", "r_in": 0.0},
                   {"plate_r_out": 0.1 / math.sqrt(math.pi), "plate_thickness": 0.02,
                    "plate_magnetization": 0.39 / MU0}),
                  ({"kind": "rectangle", "thickness": 0.02},
                   {"plate_side_x": 0.1, "plate_side_y": 0.1, "plate_thickness": 0.02,
                    "plate_magnetization": 0.39 / MU0}), -0.175, 0.05),
    }
    for label, (disk, square, mu, scale) in pairs.items():
        d = _stability_summary(*disk, g, A, C, mu, scale)
        s = _stability_summary(*square, g, A, C, mu, scale)
        rel = {k: s[k] / d[k] - 1 for k in ("z_c", "max_mass", "m_s")}
        rel["spin_lo"] = s["spin"][0] / d["spin"][0] - 1
        rel["spin_hi"] = s["spin"][1] / d["spin"][1] - 1
        print(label, "disk", d, "\n", label, "square", s, "\n", label, "square/disk - 1",
              {k: f"{v:+.2%}" for k, v in rel.items()})
        assert all(abs(v) < 0.06 for v in rel.values()), rel
        assert rel["z_c"] < 0 < rel["max_mass"]     # the square's corners: lower z_c, more lift
