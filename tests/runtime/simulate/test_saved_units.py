"""Saved files carry their units (runtime/simulate/trajectory_file.py): a CSV's first line is the
comment `# units: t=s, x=m, ...`, a .npz holds the JSON entry "units", a Parquet file the schema
metadata key "units"; the columns read back as before (the units are no column), and pandas reads
the CSV with comment="#". The answers' save writes their own units (Simulation, Scan, LaunchOdds,
built by hand: no run)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.scan_answer import Scan
from levitron.runtime.simulate import trajectory_file
from levitron.runtime.simulate.simulation import Simulation
from levitron.runtime.ui.human import Units

try:
    import pandas as pd         # the `frames` extra: imported once, at collection
except ImportError:
    pd = None

COLUMNS = {"t": np.array([0.0, 0.5, 1.0]) / 3, "z": np.array([0.1, 0.2, 0.3]),
           "verdict": np.array(["completed", "left_box", "completed"])}
UNITS = {"t": "s", "z": "m", "verdict": "text"}


def test_a_csv_starts_with_its_units_and_reads_back(tmp_path):
    path = trajectory_file.write_columns(tmp_path / "a.csv", COLUMNS, units=UNITS)
    lines = path.read_text().splitlines()
    assert lines[0] == "# units: t=s, z=m, verdict=text" and lines[1] == "t,z,verdict" and len(lines) == 5
    assert trajectory_file.read_units(path) == UNITS
    back = trajectory_file.read_columns(path)
    assert list(back) == list(COLUMNS)
    assert np.array_equal(back["t"], COLUMNS["t"]) and back["verdict"].tolist() == COLUMNS["verdict"].tolist()
    table = np.loadtxt(path, delimiter=",", skiprows=2, usecols=(0, 1))      # as the module docstring says
    assert np.array_equal(table[:, 0], COLUMNS["t"])


@pytest.mark.skipif(pd is None, reason="pandas is not installed")
def test_pandas_reads_the_csv_past_its_units_line(tmp_path):
    path = trajectory_file.write_columns(tmp_path / "a.csv", COLUMNS, units=UNITS)
    df = pd.read_csv(path, comment="#")
    assert list(df.columns) == list(COLUMNS) and np.array_equal(df["t"].to_numpy(), COLUMNS["t"])


def test_a_npz_holds_its_units_as_json_beside_the_columns(tmp_path):
    path = trajectory_file.write_columns(tmp_path / "a.npz", COLUMNS, units=UNITS)
    with np.load(path, allow_pickle=False) as data:
        assert sorted(data.files) == sorted([*COLUMNS, "units"])
        assert json.loads(str(data["units"])) == UNITS
    assert trajectory_file.read_units(path) == UNITS
    assert list(trajectory_file.read_columns(path)) == list(COLUMNS)      # the units are no column


def test_a_parquet_file_holds_its_units_in_the_schema_metadata(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    path = trajectory_file.write_columns(tmp_path / "a.parquet", COLUMNS, units=UNITS)
    assert json.loads(pq.read_schema(path).metadata[b"units"]) == UNITS
    assert trajectory_file.read_units(path) == UNITS
    assert list(trajectory_file.read_columns(path)) == list(COLUMNS)


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_a_file_written_without_units_has_none(tmp_path, suffix):
    path = trajectory_file.write_columns(tmp_path / f"a{suffix}", COLUMNS)
    assert trajectory_file.read_units(path) == {}
    assert list(trajectory_file.read_columns(path)) == list(COLUMNS)
    if suffix == ".csv":
        assert path.read_text().startswith("t,z,verdict\n")


def _sim() -> Simulation:
    tr = {"t": np.array([0.0, 0.1]), "z": np.array([0.1, 0.1]), "p_z": np.array([0.0, 1e-6]),
          "p_zeta": np.array([-1e-3, -1e-3]), "zeta": np.array([0.0, -100.0]), "energy": np.array([0.9, 0.9]),
          "L_z": np.array([1e-3, 1e-3]), "L_n": np.array([1e-3, 1e-3]), "tilt": np.zeros(2),
          "spin": np.array([1e3, 1e3])}
    return Simulation(True, 0.1, 0.0, 0.0, 10, 0.0, {}, {"status": "completed"}, tr, Units(si=True), "handmade")


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_the_answers_save_their_units(tmp_path, suffix):
    sim = _sim()
    path = sim.save(tmp_path / f"run{suffix}")
    assert trajectory_file.read_units(path) == {"t": "s", "z": "m", "p_z": "kg m/s", "p_zeta": "kg m^2/s",
                                                "zeta": "rad", "energy": "J", "L_z": "kg m^2/s",
                                                "L_n": "kg m^2/s", "tilt": "rad", "spin": "rad/s"}
    names, table = trajectory_file.read(path)
    assert names == list(sim.trajectory) and np.array_equal(table, np.column_stack(list(sim.trajectory.values())))
    scan = Scan("tilt", np.array([300.0, 1300.0]), np.array([0.01]), np.array([[False], [True]]),
                np.array([[0.2], [1.0]]), [["left_box"], ["completed"]], [{}], 1.0, {}, 0.0, {}, 0, 0.0,
                units=Units(si=False))
    path = scan.save(tmp_path / f"map{suffix}")
    assert trajectory_file.read_units(path) == {"spin": "rad/time", "tilt": "rad", "levitating": "1",
                                                "t_survived": "time units", "status": "text"}
    odds = LaunchOdds(1.0, (0.2, 1.0), 1, 1.0, {"median": 2.0, "q1": 2.0, "q3": 2.0}, [], {}, Units(si=True),
                      {"launch": np.arange(1), "mass": np.array([0.05]), "verdict": np.array(["completed"]),
                       "flight_time": np.array([2.0])}, "handmade")
    path = odds.save(tmp_path / f"odds{suffix}")
    assert trajectory_file.read_units(path) == {"launch": "1", "mass": "kg", "verdict": "text", "flight_time": "s"}
    assert list(trajectory_file.read_columns(path)) == list(odds.launches)
