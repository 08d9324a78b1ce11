"""The answers as the ecosystem's tables: `to_pandas()` of Simulation, Simulations, LaunchOdds and
Scan, `to_xarray()` of Scan and Simulation (runtime/ui/frames.py): shapes, dims named by the axes,
the units in attrs, the values the answer's own arrays bit for bit; without pandas or xarray a
one-line UserError naming the install. Answers built by hand where the numbers need no run (fast),
one real run of each kind to hold the real columns."""
from __future__ import annotations

import sys

import numpy as np
import pytest

from levitron.results import Simulations
from levitron.runtime.errors import UserError
from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.scan_answer import Scan
from levitron.runtime.simulate.simulation import Simulation
from levitron.runtime.ui.human import Units

pd = pytest.importorskip("pandas")
xr = pytest.importorskip("xarray")
xr.DataArray(np.zeros(1), dims="w", coords={"w": [0.0]})   # xarray loads its duck-array libraries (dask) once

SI, SCENE_UNITS = Units(si=True), Units(si=False)
STATES = ["x", "y", "z", "phi", "vartheta", "zeta", "p_x", "p_y", "p_z", "p_phi", "p_vartheta", "p_zeta"]
STATE_SI = ["m", "m", "m", "rad", "rad", "rad", "kg m/s", "kg m/s", "kg m/s", "kg m^2/s", "kg m^2/s", "kg m^2/s"]


def _simulation(units: Units = SI, n: int = 7) -> Simulation:
    rng = np.random.default_rng(1)
    tr = {"t": np.linspace(0.0, 0.3, n), **{s: rng.normal(size=n) for s in STATES},
          **{c: rng.normal(size=n) for c in ("energy", "L_z", "L_n", "tilt", "spin")}}
    return Simulation(True, 0.3, 1e-4, 1e-12, 100, 0.01, {s: float(tr[s][-1]) for s in STATES},
                      {"status": "completed", "t_end": 0.3}, tr, units, "handmade")


def _scan(units: Units = SI) -> Scan:
    spins, masses = np.array([300.0, 800.0, 1300.0]), np.array([0.05, 0.052])
    lev = np.array([[False, False], [True, False], [True, True]])
    t = np.array([[0.11, 0.12], [1.0, 0.5], [1.0, 1.0]])
    status = [["left_box", "left_box"], ["completed", "left_box"], ["completed", "completed"]]
    return Scan("mass", spins, masses, lev, t, status, [{"spin_interval": None, "z_s": None}] * 2, 1.0, {},
                0.1, {}, 1000, 0.2, units=units, scene="handmade")


def _odds(units: Units = SI) -> LaunchOdds:
    launches = {"launch": np.arange(4), "spin": np.array([1000.0, 1100.0, 1200.0, 1300.0]),
                "tilt": np.array([0.01, 0.02, 0.0, 0.005]), "mass": np.full(4, 0.0515),
                "z_s": np.array([0.106, 0.107, np.nan, 0.105]),
                "verdict": np.array(["completed", "left_box", "cannot_hover", "completed"]),
                "floats": np.array([1, 0, 0, 1]), "flight_time": np.array([2.0, 0.4, 0.0, 2.0])}
    return LaunchOdds(0.5, (0.15, 0.85), 4, 1.0, {"median": 1.2, "q1": 0.3, "q3": 2.0}, [], {"outcomes": {}},
                      units, launches, "handmade")


def _simulations(units: Units = SI) -> Simulations:
    n = 3
    return Simulations(np.array([True, False, False]), np.zeros(n, bool),
                       np.array(["completed", "left_box", "no_hover_height"]), np.array([1.0, 0.4, 0.0]),
                       np.array([500, 200, 0]), np.array([40, 17, 0]), np.array([0.106, 0.107, np.nan]),
                       np.arange(n * len(STATES), dtype=float).reshape(n, len(STATES)), STATES,
                       {"spin": np.array([1000.0, 1100.0, 1200.0]), "tilt": np.full(n, 0.005),
                        "top.mass": np.array([0.05, 0.051, 0.2])},
                       0.01, {"t_end": 1.0}, units, np.array([None, None, "too heavy"], dtype=object))


# ---------------------------------------------------------------- Simulation

def test_simulation_to_pandas_is_the_trajectory_with_its_units():
    sim = _simulation()
    df = sim.to_pandas()
    assert list(df.columns) == list(sim.trajectory) and len(df) == 7
    for name, col in sim.trajectory.items():
        assert np.array_equal(df[name].to_numpy(), col), name
    assert df.attrs["units"] == {"t": "s", **dict(zip(STATES, STATE_SI)), "energy": "J", "L_z": "kg m^2/s",
                                 "L_n": "kg m^2/s", "tilt": "rad", "spin": "rad/s"}
    assert df.attrs["scene"] == "handmade"


def test_simulation_to_xarray_runs_over_t():
    sim = _simulation()
    ds = sim.to_xarray()
    assert dict(ds.sizes) == {"t": 7} and list(ds.coords) == ["t"]
    assert np.array_equal(ds["t"].to_numpy(), sim.trajectory["t"]) and ds["t"].attrs["units"] == "s"
    assert set(ds.data_vars) == set(sim.trajectory) - {"t"}
    for name in ds.data_vars:
        assert ds[name].dims == ("t",) and np.array_equal(ds[name].to_numpy(), sim.trajectory[name]), name
    assert ds["p_x"].attrs["units"] == "kg m/s" and ds["p_zeta"].attrs["units"] == "kg m^2/s"
    assert ds["z"].attrs["units"] == "m" and ds["spin"].attrs["units"] == "rad/s"
    assert ds.attrs["status"] == "completed"


def test_a_dimensionless_scene_names_its_own_units():
    df = _simulation(SCENE_UNITS).to_pandas()
    u = df.attrs["units"]
    assert (u["t"], u["z"], u["phi"], u["energy"], u["spin"]) == ("time units", "scene units", "rad",
                                                                  "scene units", "rad/time")
    ds = _scan(SCENE_UNITS).to_xarray()
    assert (ds["spin"].attrs["units"], ds["mass"].attrs["units"], ds["t_survived"].attrs["units"]) == (
        "rad/time", "scene units", "time units")


def test_a_real_run_is_its_trajectory_bit_for_bit(study):
    sim = study.simulate(1100.0, tilt=0.01, t_end=0.2, n_out=40)
    df, ds = sim.to_pandas(), sim.to_xarray()
    assert df.shape == (41, len(sim.trajectory)) and list(df.columns)[:13] == ["t", *STATES]
    for name, col in sim.trajectory.items():
        assert np.array_equal(df[name].to_numpy(), col), name
        assert np.array_equal(ds[name].to_numpy(), col), name
    assert df.attrs["units"]["p_z"] == "kg m/s" and ds["t"].attrs["units"] == "s"


# ---------------------------------------------------------------- Scan

def test_scan_to_pandas_is_the_long_table():
    scan = _scan()
    df = scan.to_pandas()
    assert list(df.columns) == ["spin", "mass", "levitating", "t_survived", "status"] and len(df) == 6
    # spin-major: the row i * 2 + j is the point (spins[i], others[j])
    for i, spin in enumerate(scan.spins):
        for j, mass in enumerate(scan.others):
            row = df.iloc[i * 2 + j]
            assert (row["spin"], row["mass"]) == (spin, mass)
            assert row["levitating"] == scan.levitating[i, j] and row["t_survived"] == scan.t_survived[i, j]
            assert row["status"] == scan.status[i][j]
    assert df.attrs["units"] == {"spin": "rad/s", "mass": "kg", "levitating": "1", "t_survived": "s",
                                 "status": "text"}
    assert df.attrs["axis"] == "mass"


def test_scan_to_xarray_has_dims_named_by_the_axes():
    scan = _scan()
    ds = scan.to_xarray()
    assert dict(ds.sizes) == {"spin": 3, "mass": 2}
    assert np.array_equal(ds["spin"].to_numpy(), scan.spins) and np.array_equal(ds["mass"].to_numpy(), scan.others)
    for name in ("levitating", "t_survived", "status"):
        assert ds[name].dims == ("spin", "mass"), name
    assert np.array_equal(ds["levitating"].to_numpy(), scan.levitating)
    assert np.array_equal(ds["t_survived"].to_numpy(), scan.t_survived)
    assert ds["status"].to_numpy().tolist() == scan.status
    # a point by its coordinates, not by its place: the orientation holds
    assert bool(ds["levitating"].sel(spin=800.0, mass=0.05)) and not bool(ds["levitating"].sel(spin=800.0, mass=0.052))
    units = {n: ds[n].attrs["units"] for n in [*ds.coords, *ds.data_vars]}
    assert units == {"spin": "rad/s", "mass": "kg", "levitating": "1", "t_survived": "s", "status": "text"}
    assert ds.attrs["t_end"] == 1.0


def test_a_tilt_map_is_over_spin_and_tilt(study):
    scan = study.scan([300.0, 1300.0], "tilt", [0.01, 0.03], t_end=0.2, workers=1)
    ds = scan.to_xarray()
    assert ds["levitating"].dims == ("spin", "tilt") and ds["tilt"].attrs["units"] == "rad"
    assert np.array_equal(ds["t_survived"].to_numpy(), scan.t_survived)
    df = scan.to_pandas()
    assert list(df.columns)[:2] == ["spin", "tilt"] and df["levitating"].tolist() == scan.levitating.ravel().tolist()


# ---------------------------------------------------------------- launches

def test_launch_odds_to_pandas_is_one_row_a_launch():
    odds = _odds()
    df = odds.to_pandas()
    assert list(df.columns) == list(odds.launches) and len(df) == odds.n
    for name, col in odds.launches.items():
        assert np.array_equal(df[name].to_numpy(), col, equal_nan=col.dtype.kind == "f"), name
    assert df.attrs["units"] == {"launch": "1", "spin": "rad/s", "tilt": "rad", "mass": "kg", "z_s": "m",
                                 "verdict": "text", "floats": "1", "flight_time": "s"}
    assert df.loc[df["verdict"] == "cannot_hover", "flight_time"].tolist() == [0.0]


def test_simulations_to_pandas_is_one_row_a_launch():
    many = _simulations()
    df = many.to_pandas()
    assert len(df) == 3
    assert list(df.columns) == ["spin", "tilt", "top.mass", "levitating", "untested", "status", "t_survived",
                                "rhs_evals", "steps", "z_s", "reason", *(f"final_{s}" for s in STATES)]
    assert np.array_equal(df["top.mass"].to_numpy(), many.inputs["top.mass"])
    assert df["levitating"].tolist() == many.levitating.tolist() and df["status"].tolist() == many.status.tolist()
    assert df["reason"].tolist() == ["", "", "too heavy"]
    assert np.array_equal(df[[f"final_{s}" for s in STATES]].to_numpy(), many.final_states)
    u = df.attrs["units"]
    assert (u["spin"], u["top.mass"], u["t_survived"], u["z_s"], u["final_p_x"], u["final_phi"]) == (
        "rad/s", "kg", "s", "m", "kg m/s", "rad")


# ---------------------------------------------------------------- without pandas or xarray

@pytest.mark.parametrize("package,call", [("pandas", lambda: _simulation().to_pandas()),
                                          ("pandas", lambda: _odds().to_pandas()),
                                          ("pandas", lambda: _simulations().to_pandas()),
                                          ("xarray", lambda: _scan().to_xarray()),
                                          ("xarray", lambda: _simulation().to_xarray())])
def test_without_the_package_one_line_says_how_to_install_it(monkeypatch, package, call):
    monkeypatch.setitem(sys.modules, package, None)       # `import package` raises ImportError
    with pytest.raises(UserError) as err:
        call()
    text = str(err.value)
    assert f"pip install {package}" in text and "\n" not in text and "to_" in text
