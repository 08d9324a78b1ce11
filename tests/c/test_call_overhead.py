"""The Python around the C calls: run_c passes plain addresses carved from one buffer
(runtime/integrate/c_backend.py), and a map's chunk computes the spin-free inputs of its points once per
tilt (runtime/scan/runners.py point_setup's memo, runtime.simulate.run.Launch), with the same numbers
as before, bit for bit. Not timed, except that wall_s must contain the C run."""
from __future__ import annotations

import time

import numpy as np

from levitron.runtime.integrate import c_backend as ci
from levitron.runtime.scan.points import point_setup
from levitron.runtime.integrate.trajectory import Box


def test_buffers_are_disjoint_zeroed_and_at_their_addresses():
    sizes = (4, 7, 0, 28, 1)
    views, addrs = ci._buffers(*sizes)
    assert [v.size for v in views] == list(sizes)
    for v, a in zip(views, addrs):
        assert v.dtype == np.float64 and not v.any()
        if v.size:
            assert v.ctypes.data == a
    for k, v in enumerate(views):
        v[:] = k + 1.0                       # writing one touches no other
    assert all((v == k + 1.0).all() for k, v in enumerate(views))


def _osc(lib, method="dop853", energy=True, **kw):
    args = dict(rtol=1e-10, atol=1e-10) if method == "dop853" else dict(h=0.01)
    args.update(kw)
    return ci.run_c(lib, method, lib.lev_oscillator_rhs, [1.0, 0.0, 0.0, 1.0], [1.0], 2 * np.pi,
                    energy=lib.lev_oscillator_energy if energy else None, **args)


def test_results_own_their_arrays_and_match_the_circle(lib):
    r = _osc(lib, t_out=np.linspace(0, 2 * np.pi, 9))
    assert r.status == "completed" and r.energy is not None and len(r.energy) == len(r.t) == 9
    for a, b in ((r.x_final, r.X), (r.x_final, r.t), (r.X, r.t), (r.energy, r.X)):
        assert not np.shares_memory(a, b)
    np.testing.assert_allclose(r.X[:, 0], np.cos(r.t), atol=1e-8)
    np.testing.assert_allclose(r.x_final, [1.0, 0.0, 0.0, 1.0], atol=1e-8)
    again = _osc(lib, t_out=np.linspace(0, 2 * np.pi, 9))
    np.testing.assert_array_equal(again.x_final, r.x_final)       # no state kept between calls
    plain = _osc(lib, energy=False, t_out=np.linspace(0, 2 * np.pi, 9))
    assert plain.energy is None and plain.energy0 is None
    np.testing.assert_array_equal(plain.X, r.X)


def test_box_event_and_fixed_step_through_the_addresses(lib):
    r = _osc(lib, box=Box(iz=1, z_lo=-0.5, z_hi=0.5), t_out=np.linspace(0, 2 * np.pi, 5))
    assert r.status == "left_box" and abs(r.x_final[1] - 0.5) < 1e-8
    f = _osc(lib, "rk4", every=10, max_samples=100)
    assert f.status == "completed" and f.steps == 629 and len(f.t) == len(f.energy)


def test_wall_time_contains_the_c_run(lib):
    """wall_s times the ctypes call itself: a long run's wall_s is most of run_c's own time."""
    t = time.perf_counter()
    r = ci.run_c(lib, "rk4", lib.lev_oscillator_rhs, [1.0, 0.0, 0.0, 1.0], [1.0], 2000.0, h=1e-3)
    outside = time.perf_counter() - t
    assert r.status == "completed" and r.steps == 2_000_000
    assert 0.5 * outside < r.wall_s <= outside


def test_chunk_memo_gives_the_same_inputs_bit_for_bit(model):
    """point_setup with a chunk's memo equals point_setup alone, for every kind of map axis."""
    from levitron.runtime.physics.equilibrium.finder import hover_height
    z_s = hover_height(model)
    lighter = model.with_params({"m": 0.0505})
    z_light = hover_height(model, lighter)
    points = [dict(spin=s, tilt=t, z_s=z_s) for s in (400.0, 1200.0, -900.0) for t in (0.0, 0.05)]
    points += [dict(spin=s, height=hgt, tilt=0.01, z_s=z_s) for s in (800.0, 2000.0)
               for hgt in (-0.2, 0.3)]
    points += [dict(spin=1500.0, tilt=0.01, p=lighter, z_s=z_light), dict(spin=700.0, tilt=0.02)]
    points += [dict(spin=900.0, tilt=0.03, z_s=z_s, integrator="rk4")]
    memo: dict = {}
    for kw in points:
        a, b = point_setup(model, memo=memo, **kw), point_setup(model, **kw)
        for name in ("x0", "scale", "p"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
        assert (a.z_s, a.box, a.time_scale, a.time_scale_what, a.h) == \
               (b.z_s, b.box, b.time_scale, b.time_scale_what, b.h)
    # one launch per (parameters, hover height, tilt, height), not one per point
    launches = {k for k in memo if len(k) == 3}
    assert len(launches) == 2 + 2 + 1 + 1 + 1 < len(points)


def test_kept_output_grids_and_constants_give_the_same_runs(lib):
    """integrate's output grid is np.linspace's, kept read-only per (t_end, n_out); run_c keeps the
    work size and status messages per library: repeated runs end in the same state bit for bit,
    with their own arrays."""
    from levitron.runtime.integrate.run import output_grid
    for t_end, n in ((2 * np.pi, 1), (1.2120511047058642, 200), (1e-3, 7)):
        g = output_grid(t_end, n)
        np.testing.assert_array_equal(g, np.linspace(0.0, t_end, n + 1))
        assert g is output_grid(t_end, n) and not g.flags.writeable
    runs = [_osc(lib, t_out=output_grid(2 * np.pi, 9)) for _ in range(3)]
    fresh = _osc(lib, t_out=np.linspace(0, 2 * np.pi, 10))
    for r in runs:
        np.testing.assert_array_equal(r.x_final, fresh.x_final)
        np.testing.assert_array_equal(r.X, fresh.X)
        assert r.message == fresh.message
    assert not np.shares_memory(runs[0].X, runs[1].X) and not np.shares_memory(runs[1].X, runs[2].X)


def test_the_legendre_map_in_one_call_is_the_map_of_single_calls(model):
    """runtime/simulate/start.py legendre_map evaluates its 1 + n rows of the rhs in one C call
    (Model.rows): the same f0 and M^-1 as one Part.rhs call per row (thesis eq. 2.3.8), bit for bit."""
    from levitron.runtime.simulate.start import coordinate_names, legendre_map
    pt = model.part("full")
    s = list(pt.states)
    coords = coordinate_names(pt)
    q = np.random.default_rng(2).uniform(-0.3, 0.3, len(coords))
    q[coords.index("z")] = 0.12
    base = np.zeros(len(s))
    base[[s.index(c) for c in coords]] = q
    f0 = pt.rhs(base)[[s.index(c) for c in coords]]
    cols = []
    for c in coords:
        e = base.copy()
        e[s.index("p_" + c)] = 1.0
        cols.append(pt.rhs(e)[[s.index(c) for c in coords]] - f0)
    got_f0, got_minv = legendre_map(pt, q)
    assert np.array_equal(got_f0, f0) and np.array_equal(got_minv, np.array(cols).T)


def test_model_calls_reuse_their_buffers_and_keep_parameters_apart(model):
    """Model.call binds one CFunction per function and thread and copies p into it: calls with
    other parameters, in turn and from threads at once, each give the answer of a fresh CFunction."""
    import threading
    pt = model.part("full")
    x = np.random.default_rng(4).normal(size=pt.nx) * 0.01
    x[pt.states.index("z")] = 0.12
    ps = [model.p * (1 + 0.01 * k) for k in range(4)]
    want = [model.fast("full_rhs", p)(x) for p in ps]
    for _ in range(2):
        for p, w in zip(ps, want):
            assert np.array_equal(pt.rhs(x, p), w)
    bad = []

    def worker(k):
        for _ in range(2000):
            if not np.array_equal(pt.rhs(x, ps[k]), want[k]):
                bad.append(k)
                return

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not bad
