"""The lane variants of the generated right-hand sides (`<part>_rhs_lanes`, derive/emit/c) and the
lanes driver of the integrators (lev_integrate_lanes, through the scan's chunk driver): used only
where they give the scalar rhs's numbers bit for bit, which they do on every scene, and then the
same runs as one at a time."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.scene.load import load_scene
from levitron.scene.paths import SCENES_DIR
from levitron.runtime.model.load import load_model
from levitron.runtime.scan.chunk_c import LANES, drive, lanes_call, lanes_of, lib_verdicts, verified_lanes

SCENES = [p.stem for p in sorted(SCENES_DIR.glob("*.toml"))]


def test_one_lane_count_on_every_side():
    """LEV_LANES of integrators.h, the emitter's LANES and runtime/scan/chunk_c.py's are one number."""
    import re

    from levitron.derive.emit.c import emitter
    from levitron.scene.paths import ROOT
    header = (ROOT / "runtime" / "csrc" / "integrators.h").read_text()
    assert int(re.search(r"#define LEV_LANES (\d+)", header).group(1)) == emitter.LANES == LANES


def _states(model, part, rng, n: int) -> np.ndarray:
    """n states around the scene's hovering point: heights of 0.5..2 plate lengths, angles up to
    +-1.2 rad, momenta of either sign."""
    from levitron.runtime.physics.equilibrium.finder import scale_of
    L = scale_of(model)
    X = rng.normal(size=(n, part.nx)) * 1e-3
    for k, name in enumerate(part.states):
        if name == "z":
            X[:, k] = L * rng.uniform(0.5, 2.0, n)
        elif name in ("x", "y"):
            X[:, k] = L * rng.uniform(-0.1, 0.1, n)
        elif not name.startswith("p_"):
            X[:, k] = rng.uniform(-1.2, 1.2, n)
    return X


@pytest.mark.parametrize("name", SCENES)
def test_every_scene_has_a_verified_lane_variant_that_equals_the_scalar_rhs(name):
    """The scan takes a lane variant only after it equalled the scalar rhs bit for bit
    (runtime/scan/chunk_c.verified_lanes). Every product that is a term of a sum is fused
    explicitly (LEV_FMA, derive/emit/c/printer.py) and the compiler fuses nothing else, so
    every scene's variant passes that check (the ring magnet's too, where the compiler's own
    contraction fused one output differently in the vectorised loop) and equals the scalar rhs
    on 100 further states, with different parameters per lane and an angle beyond
    lev_sincos_lanes's range (the libm fallback) in one call."""
    model = load_model(load_scene(name))
    rng = np.random.default_rng(7)
    for part_name in model.parts:
        part = model.part(part_name)
        x0 = _states(model, part, rng, 1)[0]
        fn = verified_lanes(model, part, x0, model.p, np.maximum(np.abs(x0), 1e-3))
        assert lanes_of(model, f"{part_name}_rhs") is not None, f"{name}: {part_name}_rhs_lanes missing"
        assert fn is not None, f"{name} {part_name}: the lane variant differs from the scalar rhs"
        for trial in range(25):
            X = _states(model, part, rng, LANES)
            if trial == 24:
                angles = [k for k, s in enumerate(part.states) if not s.startswith("p_")
                          and s not in ("x", "y", "z")]
                if angles:
                    X[1, angles[0]] = 3.0e5          # beyond lev_sincos_lanes's range
            P = np.array([model.p * (1 + 0.01 * lane) for lane in range(LANES)])
            got = lanes_call(fn, X, P)
            for lane in range(LANES):
                want = part.rhs(X[lane], P[lane])
                np.testing.assert_array_equal(got[lane], want, err_msg=f"{name} {part_name} lane {lane}")


def test_a_differing_lane_variant_is_refused(monkeypatch):
    """verified_lanes compares with the scalar rhs: make the scalar one an ulp off and the lane
    variant is refused."""
    model = load_model(load_scene("loop"))
    part = model.part("full")
    rhs = part.rhs
    monkeypatch.setattr(part, "rhs", lambda x, p=None: np.nextafter(rhs(x, p), np.inf))
    x0 = _states(model, part, np.random.default_rng(1), 1)[0]
    lib_verdicts(model.lib).pop("full_rhs", None)
    try:
        assert verified_lanes(model, part, x0, model.p, np.maximum(np.abs(x0), 1e-3)) is None
    finally:
        lib_verdicts(model.lib).pop("full_rhs", None)


@pytest.mark.parametrize("method", ["dop853", "vern9"])
def test_lanes_driver_equals_one_run_at_a_time(method):
    """lev_integrate_lanes (LEV_LANES runs per rhs call, lanes refilled as runs end, a free lane
    repeating another) against lev_integrate one point at a time: the same status, end time, rhs
    count, steps and final state for every point, falling ones included (7 points: not a
    multiple of the lanes)."""
    from levitron.runtime.scan.points import point_setup
    model = load_model(load_scene("thesis_stable"))
    pt = model.part("full")
    tol = 1e-9
    sus = [point_setup(model, spin, tilt) for spin, tilt in
           [(300.0, 0.0), (900.0, 0.05), (1500.0, 0.1), (2500.0, 0.02), (4000.0, 0.2),
            (1200.0, 0.15), (700.0, 0.01)]]
    args = (model.lib, method, pt.c_function("rhs"), None, 2.0, tol, sus[0].box.ix, sus[0].box.iy,
            sus[0].box.iz, np.array([s.x0 for s in sus]), np.array([s.p for s in sus]),
            np.array([tol * s.scale for s in sus]), np.zeros(len(sus)),
            np.array([(s.box.z_lo, s.box.z_hi, s.box.r_max) for s in sus]),
            np.full(len(sus), 10**7))
    fn = verified_lanes(model, pt, sus[1].x0, sus[1].p, sus[1].scale)
    assert fn is not None, "thesis_stable's lane variant differs from its scalar rhs"
    one = drive(*args)
    lanes = drive(*args, rhs_lanes=fn)
    assert one["status"] == lanes["status"] and "left_box" in one["status"] and "completed" in one["status"]
    for key in ("t_final", "rhs_evals", "steps", "x_final"):
        np.testing.assert_array_equal(lanes[key], one[key], err_msg=key)
