"""The launches as data (issue 26): `levitron launch --save FILE` writes every sampled input, the
verdict and the flight time of each launch; `Study.launch()` returns the same table as arrays.

The checks: the file's rows reproduce the JSON's counts (outcomes, successes, flight times), the
API's table (another route: no CLI, the same seed) is the file's, and a row's inputs, given back to
`launch --n 1` as fixed numbers (the mass in kg, the strength as the factor), fly that launch again
to the same verdict and the same flight time."""
from __future__ import annotations

import collections
import json

import numpy as np
import pytest

import levitron as lev
from levitron.runtime.cli.main import main
from levitron.runtime.scan import launch_inputs as li
from levitron.runtime.scan import launch_summary as ls
from levitron.runtime.simulate import trajectory_file

N, T_END = 30, 3.0
ARGS = ["launch", "thesis_air", "--n", str(N), "--t-end", str(T_END), "--seed", "5"]


def _run(capsys, *extra) -> dict:
    assert main([*ARGS, *extra, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def api():
    return lev.load("thesis_air").launch(n=N, seed=5, t_end=T_END)


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_the_saved_rows_reproduce_the_json(tmp_path, capsys, suffix, api):
    path = tmp_path / f"launches{suffix}"
    r = _run(capsys, "--save", str(path))
    assert r["saved"]["path"] == str(path) and r["saved"]["rows"] == N and "launches" not in r
    level = [k for k in ls.LAUNCH_UNITS if k not in {a.name for a in li.APPARATUS}]   # a level scene's
    assert list(r["saved"]["columns"]) == level
    assert r["saved"]["columns"]["mass"] == "kg" and r["saved"]["columns"]["spin"] == "rad/s"
    assert not list(tmp_path.glob(".launches*"))            # the temporary file was renamed away
    t = trajectory_file.read_columns(path)
    assert list(t) == level and all(len(v) == N for v in t.values())
    np.testing.assert_array_equal(t["launch"], np.arange(N))
    assert dict(collections.Counter(t["verdict"].tolist())) == r["outcomes"]
    assert int(t["floats"].sum()) == r["successes"]
    assert t["floats"].astype(bool).tolist() == r["verdicts"]
    assert t["flight_time"].tolist() == r["flight_time"]["values"]
    assert 0 < r["successes"] < N             # the sample has both verdicts: the counts test something
    # the API's table is the file's, column by column, to the last bit
    assert list(api.launches) == list(t)
    for k, v in api.launches.items():
        assert np.asarray(v).tolist() == t[k].tolist(), k
    # the mass is the mass in kg as run (the scene's 51.5 g with its relative spread), the strength a factor
    # (the default spreads: 0.2 % and 0.5 % relative sd, so every launch within 5 sd), and mu the
    # moment the run used, the scene's times the strength (the scene's temperature: no factor)
    study = lev.load("thesis_air")
    m0, mu0 = study.value("top.mass"), study.model.param("mu")
    assert np.all(np.abs(t["mass"] / m0 - 1) < 0.01) and np.all(np.abs(t["strength"] - 1) < 0.025)
    np.testing.assert_allclose(t["mu"], mu0 * t["strength"], rtol=1e-15)
    hovers = t["verdict"] != "cannot_hover"
    assert np.all(np.isfinite(t["z_s"][hovers]))


def test_a_saved_row_flies_again_to_the_same_verdict(tmp_path, capsys):
    path = tmp_path / "launches.csv"
    _run(capsys, "--save", str(path))
    t = trajectory_file.read_columns(path)
    fell = int(np.flatnonzero(t["verdict"] == "left_box")[0])
    up = int(np.flatnonzero(t["verdict"] == "completed")[0])
    for i in (fell, up):
        fixed = [f"--{k.replace('_', '-')}" if k != "temperature" else "--temperature-spread"
                 for k in li.INPUTS]
        values = [repr(float(t[k][i])) for k in li.INPUTS]
        again = _run(capsys, *[f"{f}={v}" for f, v in zip(fixed, values)], "--n", "1")
        assert again["outcomes"] == {str(t["verdict"][i]): 1}
        assert again["flight_time"]["values"][0] == pytest.approx(t["flight_time"][i], rel=1e-12)
        assert again["successes"] == int(t["floats"][i])


def test_the_api_saves_the_same_table(tmp_path, api):
    path = api.save(tmp_path / "api.npz")
    back = trajectory_file.read_columns(path)
    assert list(back) == list(api.launches)
    for k in back:
        assert back[k].tolist() == np.asarray(api.launches[k]).tolist()
    assert isinstance(api.launches["spin"], np.ndarray) and "launches" not in api.details


def test_a_bad_save_path_is_refused_before_the_run(tmp_path, capsys):
    assert main([*ARGS, "--save", str(tmp_path / "launches.txt")]) == 2
    err = capsys.readouterr().err.strip()
    assert ".csv, .npz or .parquet" in err and "\n" not in err


def test_parquet_round_trips(tmp_path, api):
    pytest.importorskip("pyarrow")
    back = trajectory_file.read_columns(api.save(tmp_path / "api.parquet"))
    for k in api.launches:
        assert back[k].tolist() == np.asarray(api.launches[k]).tolist()
