"""`levitron scan`: stability maps over spin and tilt / mass / height (docs/contract.md `scan`; thesis fig.
3.8 after Gans et al.). The scene is the thesis plate with a 51.5 g top (`--set top.mass=0.0515`),
which hovers at z_s = 10.65 cm inside the stable band with the linear spin interval ~[460, 2740]
rad/s (thesis 3.3); the thesis's own 28.4 g top is not stabilisable by any spin."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from levitron.runtime.scan import stability_map as sc
from levitron.runtime.physics.routes.eigen_route import full_equilibrium_state
from levitron.runtime.errors import UserError
from levitron.runtime.scan.grid import parse_range
from levitron.runtime.scan.physics import linear_interval
from levitron.runtime.scan.points import N_OUT, point_run
from levitron.runtime.physics.stability.analysis import model_callables

ROOT = Path(__file__).resolve().parents[3]
SET = ["top.mass=0.0515"]        # the `model` fixture's setting (tests/conftest.py LIGHT_TOP)
BASE = [sys.executable, "-m", "levitron.runtime.cli.main", "scan", "thesis", "--set", SET[0]]


def run_scan(model, spins, axis, others, **kw):
    kw.setdefault("quiet", True)
    return sc.scan(model, np.asarray(spins, float), axis, np.asarray(others, float), **kw)


def cli(*args, check_json=True):
    res = subprocess.run(BASE + list(args), capture_output=True, text=True, cwd=ROOT, check=False)
    if check_json:
        assert res.returncode == 0, res.stderr
        return json.loads(res.stdout)
    return res


def test_cli_small_grid_binding_keys_and_picture(tmp_path):
    """3 x 2 grid through the command line: docs/contract.md keys, [i_spin][j_other] shapes, the PNG."""
    png = tmp_path / "map.png"
    d = cli("--spin", "300:1500:3", "--tilt", "0.01:0.02:2", "--t-end", "1", "--json", "--out", str(png))
    for key in ("grid", "levitating", "wall_s", "t_survived", "spin_interval", "linear"):
        assert key in d
    assert d["grid"] == {"spin": [300.0, 900.0, 1500.0], "tilt": [0.01, 0.02]}
    assert len(d["levitating"]) == 3 and all(len(r) == 2 for r in d["levitating"])
    assert all(isinstance(v, bool) for r in d["levitating"] for v in r)
    assert np.shape(d["t_survived"]) == (3, 2)
    assert d["wall_s"] > 0 and d["t_end"] == 1.0
    lo, hi = d["spin_interval"]
    assert 440 < lo < 480 and 2700 < hi < 2780
    # 300 rad/s is below the interval: the top falls within the second; 900 rad/s holds
    assert d["levitating"][0] == [False, False] and d["levitating"][1] == [True, True]
    assert png.stat().st_size > 10_000 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_inside_linear_interval_levitates_outside_does_not(model):
    """Default run length; tiny tilt. 1000 rad/s (inside [460, 2740]) stays up; 150 rad/s (well
    below) and 4000 rad/s (above: the fast top is linearly unstable too, thesis 3.3) fall."""
    res = run_scan(model, [150.0, 1000.0, 4000.0], "tilt", [0.01])
    assert res.levitating[:, 0].tolist() == [False, True, False]
    assert res.t_survived[1, 0] == pytest.approx(res.t_end)
    assert res.t_survived[0, 0] < 0.5 * res.t_end and res.t_survived[2, 0] < res.t_end
    assert res.linear[0]["spin_interval"][0] < 1000 < res.linear[0]["spin_interval"][1]
    assert res.agreement() == 1.0


def test_default_t_end_is_three_slow_periods(model):
    """The default run length is PERIODS periods of the slowest motion at the relative equilibrium:
    checked against the eigenvalues of the generated full model's Jacobian (thesis 3.3.5), not the
    8-D matrix the scan uses."""
    res = run_scan(model, [1000.0], "tilt", [0.01])
    b = res.t_end_basis
    onaxis, jac, states = model_callables(model)
    z_s = res.linear[0]["z_s"]
    C = model.param("C")
    lam = np.linalg.eigvals(jac(full_equilibrium_state(states, z_s, C, b["reference_spin"])))
    im = np.abs(lam.imag)
    slowest = im[im > 1e-6].min()
    bounce = 2 * math.pi * math.sqrt(model.param("m") / (model.param("mu") * onaxis(z_s)[3]))
    assert b["slow_period_s"] == pytest.approx(max(2 * math.pi / slowest, bounce), rel=1e-8)
    assert res.t_end == pytest.approx(sc.PERIODS * b["slow_period_s"])
    assert 5.0 < res.t_end < 20.0


def test_workers_equal_serial(model):
    spins, tilts = [300.0, 1000.0, 2000.0, 3200.0], [0.01, 0.06]
    a = run_scan(model, spins, "tilt", tilts, t_end=2.0, workers=1)
    b = run_scan(model, spins, "tilt", tilts, t_end=2.0, workers=2)
    assert b.runner == {"kind": "processes", "workers": 2, "chunks": 8, "engine": "c"}
    assert a.runner["kind"] == "serial" and a.runner["engine"] == "c"
    assert a.status == b.status
    np.testing.assert_array_equal(a.levitating, b.levitating)
    np.testing.assert_array_equal(a.t_survived, b.t_survived)
    assert a.levitating.any() and not a.levitating.all()


def test_mass_axis_each_top_at_its_own_hover_height(model):
    """m is a runtime parameter: 51.5 g hovers in the band and levitates at 1000 rad/s; 40 g hovers
    higher (outside the band: no spin stabilises it) and falls; 70 g exceeds what the plate holds."""
    res = run_scan(model, [1000.0], "mass", [0.040, 0.0515, 0.070], t_end=4.0)
    assert res.levitating[0].tolist() == [False, True, False]
    assert res.status[0][2] == "no_hover_height" and res.t_survived[0, 2] == 0.0
    zs = [li["z_s"] for li in res.linear]
    assert zs[0] > zs[1] > 0 and zs[2] is None
    assert res.linear[0]["spin_interval"] is None and res.linear[1]["spin_interval"] is not None
    d = res.as_json()
    assert d["grid"]["mass"] == [0.040, 0.0515, 0.070] and d["base_tilt"] == sc.BASE_TILT


def test_height_axis_is_a_fraction_of_z_s(model):
    """--height h starts the top at z_s (1 + h), at rest: a turning point of the vertical bounce
    about z_s (thesis 3.3.3), so the height deviation reaches |h| z_s and, the potential being
    only mildly anharmonic over 2 % of z_s, not much more (an amount in m would be 10x off)."""
    z_s = linear_interval(model)["z_s"]
    for h in (0.02, -0.02):
        r = point_run(model, 1000.0, 0.0, h, 1.0, "dop853", 1e-10, n_out=400)
        assert r["levitating"]
        assert abs(h) * z_s * (1 - 1e-9) <= r["max_height_deviation"] < 1.25 * abs(h) * z_s
    res = run_scan(model, [1000.0], "height", [-0.02, 0.0, 0.02], t_end=2.0)
    assert res.levitating.all()


def test_point_run_is_simulate(model):
    """The scan's runner, at height 0 with z_s given, is runtime.simulate.run.simulate number for number."""
    from levitron.runtime.simulate.run import simulate
    from levitron.runtime.physics.equilibrium.finder import hover_height
    z_s = hover_height(model)
    for spin, tilt in ((1000.0, 0.03), (3000.0, 0.01)):
        a = simulate(model, spin, tilt=tilt, t_end=3.0, n_out=N_OUT)
        b = point_run(model, spin, tilt=tilt, t_end=3.0, z_s=z_s)
        for key in ("levitating", "t_survived", "rhs_evals", "final_state", "max_excursion"):
            assert a[key] == b[key], key


def test_negative_range_on_the_command_line():
    d = cli("--spin", "1000:1000:1", "--height", "-0.02:0.02:2", "--t-end", "0.5", "--json", "--quiet")
    assert d["grid"]["height"] == [-0.02, 0.02] and d["levitating"] == [[True, True]]


@pytest.mark.parametrize("args, words", [
    (["--spin", "100:200:0", "--tilt", "0.01:0.1:2"], "at least 1"),
    (["--spin", "900:100:3", "--tilt", "0.01:0.1:2"], "above"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--mass", "0.05:0.06:2"], "exactly one"),
    (["--spin", "100:900:3"], "exactly one"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--t-end", "-1"], "positive"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--workers", "0"], "workers"),
    (["--spin", "100:900:3", "--height", "0:0.6:2"], "between -0.5 and 0.5"),
    (["--spin", "100:900", "--tilt", "0.01:0.1:2"], "LO:HI:N"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--tol", "1"], "too loose"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--t-end", "1e9"], "budget cap"),
    (["--spin", "100:1e12:2", "--tilt", "0.01:0.1:2", "--t-end", "1"], "spin period"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--integrator", "rk4", "--step", "1e-12"], "below 1e-09"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--step", "1e-4"], "adaptive"),
    (["--spin", "100:900:3", "--tilt", "0.01:0.1:2", "--integrator", "verlet"], "unknown integrator"),
])
def test_bad_options_exit_2(args, words):
    """One error line: on a cold cache the compile's progress notes ("levitron: compiling ...")
    come first, and are not the refusal (tests/helpers/hostile.py error_lines)."""
    from tests.helpers.hostile import error_lines
    res = cli(*args, check_json=False)
    assert res.returncode == 2, res.stderr
    assert words in res.stderr and res.stdout == ""
    assert len(error_lines(res.stderr)) == 1, res.stderr


def test_scheduler_without_dask_is_a_user_error(model, monkeypatch):
    """Without dask.distributed (hidden here: None in sys.modules makes the import fail) --scheduler
    is a one-line UserError naming the extra to install."""
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(UserError, match="dask"):
        run_scan(model, [1000.0], "tilt", [0.01], t_end=0.1, scheduler="tcp://127.0.0.1:1")


def test_parse_range():
    np.testing.assert_allclose(parse_range("0:1:5", "tilt"), [0, 0.25, 0.5, 0.75, 1])
    assert parse_range("2:2:1", "tilt").tolist() == [2.0]
    for bad in ("1:2:1", "a:1:2", "0:1:2.5", "0:nan:3"):
        with pytest.raises(UserError):
            parse_range(bad, "tilt")


def _stopped_early_map():
    """A 3 x 2 map (spin x tilt) whose tilt-1e-5 row ran out of its step budget at every spin (as
    z-x-z angles do near the upright top: `scan thesis_stable --set model.coordinates="euler-zxz"
    --spin 600:2000:3 --tilt 1e-5:1e-3:3 --t-end 0.5`) while the other row stayed up."""
    spins, tilts = np.array([600.0, 1300.0, 2000.0]), np.array([1e-5, 1e-3])
    lev = np.array([[False, True]] * 3)
    ts = np.array([[1.7e-6, 0.5]] * 3)
    status = [["step_budget", "completed"] for _ in spins]
    lin = [{"spin_interval": [459.6, 2740.0], "z_s": 0.1065}] * 2
    return sc.Scan("tilt", spins, tilts, lev, ts, status, lin, 0.5, {"given": True}, 0.1,
                         {"kind": "serial", "workers": 1}, 0, 0.1)


def test_runs_stopped_early_are_no_verdict_not_falls(tmp_path, legend_texts):
    """A run that stops on its step budget (or a non-finite state, a step underflow) says nothing of
    the top: the summary used to print "falls at every spin (0 of 3)" for such a row, and the map
    painted it as 'fell at once'. The row now names the runs without a verdict and the map marks
    them in their own colour (as it does the points that cannot hover)."""
    from levitron.runtime.cli.commands.scan import human
    from levitron.runtime.scan.plot import draw
    res = _stopped_early_map()
    r = res.as_json()
    r.update(points=6, runner={"kind": "serial", "workers": 1}, wall_s=0.1)
    text = human(r)
    row = next(line for line in text.splitlines() if "tilt 1e-5" in line)
    assert "falls" not in row, row
    assert "no verdict" in row and "step_budget" in row and "3 of 3" in row, row
    other = next(line for line in text.splitlines() if "tilt 0.001" in line)
    assert "stays up for spin" in other and "no verdict" not in other, other
    draw(res, tmp_path / "m.png")
    assert any("no verdict" in t for t in legend_texts), legend_texts
