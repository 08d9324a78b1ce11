"""One answer type per question (issue 29): the command line's JSON is the answer's as_json(), the
API returns the same type, and the answer's numbers hold against an independent route (the
equilibrium condition by hand, the energy of the saved states)."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

import levitron as lev
from levitron.runtime.cli import main as cli
from levitron.runtime.design.design_answer import Design
from levitron.runtime.design.fit_answer import Fit
from levitron.runtime.physics.equilibrium.answer import Equilibria
from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.scan_answer import Scan
from levitron.runtime.simulate.simulation import Simulation

SCENE = "thesis_stable"
RUN = dict(spin=1100.0, tilt=0.01, t_end=0.3, n_out=60)


def _cli_json(capsys, *argv) -> dict:
    assert cli.main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _same(a, b, skip=("wall_s", "provenance")) -> None:
    """a and b equal key for key (numbers bit for bit, as JSON writes them), but for `skip`."""
    skip = (*skip, "success") if "success" not in b else skip    # the API's property, not in its as_json
    a = {k: v for k, v in a.items() if k not in skip}               # (tests/cli/test_json_success.py)
    b = {k: v for k, v in b.items() if k not in skip}
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def test_equilibria_is_one_answer_for_the_api_and_the_command_line(study, capsys):
    eq = study.equilibria()
    assert type(eq) is Equilibria and lev.Equilibria is Equilibria
    _same(_cli_json(capsys, "equilibrium", SCENE), cli._clean(eq.as_json()))


def test_equilibria_satisfy_the_equilibrium_condition_by_hand(study):
    """m g + mu Phi_2(z) = 0 at every equilibrium and U'' = mu Phi_3 its stiffness (thesis 3.3.2-3.3.3),
    from the generated on-axis functions; the band's attributes are its Band's."""
    eq = study.equilibria()
    P = study.model.pvals()
    assert len(eq.equilibria) == 2 and eq.success
    for e in eq.equilibria:
        phi = study.model.onaxis(e.z)
        assert abs(P["m"] * P["g"] + P["mu"] * phi[2]) <= 1e-12 * P["m"] * P["g"]
        assert e.stiffness == pytest.approx(P["mu"] * phi[3], rel=1e-12)
        assert e.vertically_stable == (e.stiffness > 0)
    assert eq.stable_band_z == tuple(eq.stable_band.z) and eq.stable_band_mass == tuple(eq.stable_band.mass)
    lo, hi = eq.stable_band.mass
    assert lo < P["m"] < hi and eq.reason is None and eq.reasons == []
    # the heaviest top hovers at z_c, where Phi_3 vanishes: m(z_c) = -mu Phi_2(z_c) / g
    phi_c = study.model.onaxis(eq.z_c)
    assert eq.max_mass == pytest.approx(-P["mu"] * phi_c[2] / P["g"], rel=1e-12)


def test_simulations_is_the_answer_beside_simulate_many(study):
    """Study.simulate_many's answer lives beside runtime/scan/batch.py simulate_many, re-exported by
    levitron.results and levitron, and its runs are simulate()'s (tests/runtime/scan/test_batch.py)."""
    from levitron import results
    from levitron.runtime.scan.batch_answer import Simulations
    many = study.simulate_many([RUN["spin"]], tilt=RUN["tilt"], t_end=RUN["t_end"])
    assert type(many) is Simulations and lev.Simulations is Simulations and results.Simulations is Simulations
    one = study.simulate(**RUN)
    assert many.levitating[0] == one.levitating and many.t_survived[0] == one.t_survived


def test_a_dimensionless_scene_repr_has_no_si_unit():
    eq = lev.load(SCENE, {"units": "dimensionless"}).equilibria()
    text = repr(eq) + repr(eq.equilibria[0]) + eq.message
    assert "0.1065 (vertically stable)" in text and "z: 0.09351" in text
    assert not re.search(r"\d ?(m|kg|N/m)\b", text), text


def test_simulation_is_one_answer_for_the_api_and_the_command_line(study, capsys):
    sim = study.simulate(**RUN)
    assert type(sim) is Simulation and lev.Simulation is Simulation
    argv = ["simulate", SCENE, "--spin", "1100", "--tilt", "0.01", "--t-end", "0.3", "--n-out", "60"]
    out = _cli_json(capsys, *argv)
    assert out.pop("plot") is None and "linear" in out      # the command's own keys
    out.pop("linear")
    _same(out, cli._clean(sim.as_json()))
    assert sim["levitating"] is sim.levitating is True and sim.t_survived == RUN["t_end"]


def test_simulation_samples_hold_the_energy_and_the_final_state(study, tmp_path):
    """The trajectory's energy column is H of its own states (the generated energy, row by row),
    its largest drift the answer's energy_drift; its last row the final state; save round-trips it;
    plot draws it."""
    from levitron.runtime.simulate import trajectory_file
    sim = study.simulate(**RUN)
    pt = study.model.part("full")
    tr = sim.trajectory
    X = np.column_stack([tr[s] for s in pt.states])
    H = np.array([pt.energy(x, study.model.p) for x in X])
    np.testing.assert_allclose(tr["energy"], H, rtol=1e-13, atol=0)
    drift = np.max(np.abs(H - H[0])) / sim["energy_scale"]
    assert drift == pytest.approx(sim.energy_drift, rel=1e-6, abs=1e-15)
    assert X[-1].tolist() == pytest.approx([sim.final_state[s] for s in pt.states], rel=1e-15, abs=1e-300)
    names, table = trajectory_file.read(sim.save(tmp_path / "run.npz"))
    assert names == list(tr) and np.array_equal(table, np.column_stack([tr[n] for n in names]))
    assert sim.plot(tmp_path / "run.png").axes          # the Figure, written to the path
    assert (tmp_path / "run.png").stat().st_size > 5000


def test_simulate_returns_no_file_unless_asked(study, tmp_path):
    """Plotting and saving are the answer's actions, not simulate()'s: the runtime's simulate takes
    neither, and Study.simulate's plot= and save= call them."""
    import inspect

    from levitron.runtime.simulate import trajectory_file
    from levitron.runtime.simulate.run import simulate
    assert not {"plot", "save", "trajectory"} & set(inspect.signature(simulate).parameters)
    study.simulate(**RUN, plot=tmp_path / "a.png", save=tmp_path / "a.csv")
    assert (tmp_path / "a.png").stat().st_size > 5000
    names, table = trajectory_file.read(tmp_path / "a.csv")
    assert table.shape == (RUN["n_out"] + 1, len(names))


MAP = dict(spins=[300.0, 1300.0], axis="tilt", values=[0.01, 0.03], t_end=1.0)
MAP_ARGV = ["scan", SCENE, "--spin", "300:1300:2", "--tilt", "0.01:0.03:2", "--t-end", "1"]


@pytest.fixture(scope="module")
def scan_map(study):
    return study.scan(MAP["spins"], MAP["axis"], MAP["values"], t_end=MAP["t_end"])


def test_scan_is_one_answer_for_the_api_and_the_command_line(scan_map, capsys):
    assert type(scan_map) is Scan and lev.Scan is Scan and lev.ScanResult is Scan
    out = _cli_json(capsys, *MAP_ARGV)
    assert out.pop("out") is None and "saved" not in out      # the command's own keys
    _same(out, cli._clean(scan_map.as_json()), skip=("wall_s", "cpu_s", "provenance"))
    assert out["scene"] == SCENE and out["points"] == scan_map.points == 4


def test_scan_points_are_single_simulations(study, scan_map):
    """Every point of the map is the run Study.simulate makes from the same start (an independent
    route: one Python-driven run per point against the C chunk driver), to the last bit of
    t_survived; the counts add up to the grid and to the JSON's map."""
    from levitron.runtime.scan.points import N_OUT
    for i, spin in enumerate(MAP["spins"]):
        for j, tilt in enumerate(MAP["values"]):
            sim = study.simulate(spin, tilt=tilt, t_end=MAP["t_end"], n_out=N_OUT)
            assert scan_map.levitating[i, j] == sim.levitating
            assert scan_map.t_survived[i, j] == sim.t_survived
            assert scan_map.status[i][j] == sim.status
    assert scan_map.levitating.tolist() == [[False, False], [True, True]]    # 300 rad/s: below the interval
    c = scan_map.counts
    assert c == {"levitating": 2, "fell": 2, "no_verdict": 0, "cannot_hover": 0}
    assert sum(c.values()) == scan_map.points
    assert c["levitating"] == sum(map(sum, scan_map.as_json()["levitating"]))


def test_scan_actions_write_the_map_and_its_points(scan_map, tmp_path, capsys):
    """save writes one row a point that reads back as the JSON's nested lists; plot draws the
    map; the command's --save and --out call them."""
    from levitron.runtime.simulate import trajectory_file
    d = scan_map.as_json()
    cols = trajectory_file.read_columns(scan_map.save(tmp_path / "map.npz"))
    assert list(cols) == ["spin", "tilt", "levitating", "t_survived", "status"]
    assert cols["spin"].reshape(2, 2).tolist() == [[s, s] for s in d["grid"]["spin"]]
    assert cols["tilt"].reshape(2, 2).tolist() == [d["grid"]["tilt"]] * 2
    assert cols["levitating"].reshape(2, 2).tolist() == d["levitating"]
    assert cols["t_survived"].reshape(2, 2).tolist() == d["t_survived"]
    assert cols["status"].reshape(2, 2).tolist() == d["status"]
    assert scan_map.plot(tmp_path / "map.png").axes     # the Figure, written to the path
    assert (tmp_path / "map.png").stat().st_size > 10_000
    out = _cli_json(capsys, *MAP_ARGV, "--save", str(tmp_path / "cli.csv"), "--out", str(tmp_path / "cli.png"))
    assert out["saved"] == str(tmp_path / "cli.csv") and out["out"] == str(tmp_path / "cli.png")
    csv = trajectory_file.read_columns(tmp_path / "cli.csv")
    assert csv["t_survived"].tolist() == cols["t_survived"].tolist()      # %.17g: every double back
    assert csv["status"].tolist() == cols["status"].tolist()


ODDS = dict(n=12, seed=3, t_end=0.5)
ODDS_ARGV = ["launch", SCENE, "--n", "12", "--seed", "3", "--t-end", "0.5"]


@pytest.fixture(scope="module")
def odds(study):
    return study.launch(**ODDS)


def test_launch_odds_is_one_answer_for_the_api_and_the_command_line(odds, capsys):
    from levitron.runtime.scan import launch_odds as mc
    assert type(odds) is LaunchOdds and lev.LaunchOdds is LaunchOdds
    out = _cli_json(capsys, *ODDS_ARGV)
    assert out.pop("saved") is None and out.pop("out") is None        # the command's own keys
    _same(out, cli._clean(odds.as_json()))
    assert out["scene"] == SCENE and "launches" not in out            # the table goes to --save
    # the runtime returns the same answer the API does
    again = mc.Request({}, **ODDS).run(lev.load(SCENE).model, quiet=True)
    assert type(again) is LaunchOdds and again["verdicts"] == odds["verdicts"]


def test_launch_odds_hold_against_their_own_launches(odds):
    """The odds are the launches' own count (the table's floats column, the flight times against
    the success time) and their interval Wilson's score interval by hand (Wilson 1927, z = 1.96)."""
    t = odds.launches["flight_time"]
    floats = t >= odds.success_time * (1 - 1e-12)
    assert odds.launches["floats"].tolist() == floats.astype(int).tolist()
    decided = odds.n - odds["no_verdict"]
    k = int(floats.sum())
    assert odds["successes"] == k and odds.probability == k / decided
    z, p = 1.959963984540054, k / decided
    mid = (p + z * z / (2 * decided)) / (1 + z * z / decided)
    half = z * np.sqrt(p * (1 - p) / decided + z * z / (4 * decided ** 2)) / (1 + z * z / decided)
    assert odds.probability_ci95 == pytest.approx((mid - half, mid + half), rel=1e-12, abs=1e-15)
    assert odds.flight_time["median"] == pytest.approx(float(np.median(t)), rel=1e-15)
    assert odds["flight_time"]["values"] == t.tolist()


def test_launch_odds_actions_write_the_launches_and_the_histogram(odds, tmp_path, capsys):
    from levitron.runtime.simulate import trajectory_file
    cols = trajectory_file.read_columns(odds.save(tmp_path / "odds.npz"))
    assert list(cols) == list(odds.launches)
    for name, col in odds.launches.items():
        assert np.array_equal(cols[name], col), name
    assert odds.plot(tmp_path / "odds.png").axes        # the Figure, written to the path
    assert (tmp_path / "odds.png").stat().st_size > 5000
    out = _cli_json(capsys, *ODDS_ARGV, "--save", str(tmp_path / "cli.csv"), "--out", str(tmp_path / "cli.png"))
    assert out["saved"]["path"] == str(tmp_path / "cli.csv") and out["saved"]["rows"] == ODDS["n"]
    assert out["out"] == str(tmp_path / "cli.png") and (tmp_path / "cli.png").stat().st_size > 5000
    csv = trajectory_file.read_columns(tmp_path / "cli.csv")
    assert csv["flight_time"].tolist() == cols["flight_time"].tolist()
    assert csv["verdict"].tolist() == cols["verdict"].tolist()


VARY = {"top.mass": (0.0505, 0.0524)}
VARY_ARGV = ["optimize", SCENE, "--maximize", "spin-range", "--vary", "top.mass=0.0505:0.0524"]


@pytest.fixture(scope="module")
def design(study):
    return study.optimize("spin-range", VARY)


def test_design_is_one_answer_for_the_api_and_the_command_line(design, capsys):
    assert type(design) is Design and lev.Design is Design and lev.DesignResult is Design
    out = _cli_json(capsys, *VARY_ARGV)
    assert "written" not in out                   # the command's own key, only with --write-scene
    _same(out, cli._clean(design.as_json()))
    assert out["scene"] == SCENE == design.scene.name


def test_design_optimum_holds_by_the_stability_route(design):
    """At the optimum the scene's own stability answer (Study.stability on the scene loaded with the
    optimum, the exact discriminant route) gives the design's interval and objective."""
    at = lev.load(SCENE, design.optimum).stability()
    assert at.spin_interval == pytest.approx(design.spin_interval, rel=1e-9)
    assert design.value == pytest.approx(at.spin_interval[1] - at.spin_interval[0], rel=1e-9)
    assert at.z_s == pytest.approx(design.z_s, rel=1e-12)


def test_design_writes_the_scene_at_its_optimum(design, tmp_path, capsys):
    """write_scene writes a scene that loads back with the optimum's key and the design's answer;
    --write-scene calls it."""
    path = design.write_scene(tmp_path / "best.toml")
    assert path == str(tmp_path / "best.toml")
    text = (tmp_path / "best.toml").read_text()
    assert text.startswith("# levitron optimize thesis_stable --maximize spin-range: top.mass = ")
    again = lev.load(path)
    # the optimum written as its shortest decimal within a millionth (scene_write.shortest): the
    # window moves by about as much
    assert again.value("top.mass") == pytest.approx(design.optimum["top.mass"], rel=1e-6)
    assert again.stability().spin_interval == pytest.approx(design.spin_interval, rel=1e-5)
    (tmp_path / "cli").mkdir()
    out = _cli_json(capsys, *VARY_ARGV, "--write-scene", str(tmp_path / "cli" / "best.toml"))
    assert out["written"] == str(tmp_path / "cli" / "best.toml")
    assert (tmp_path / "cli" / "best.toml").read_text() == text


FIT_CSV = """quantity,value,sigma,overrides
z_s,0.1065,1e-4,top.mass=0.0515
z_s,0.1052,1e-4,top.mass=0.0518
z_s,0.1078,1e-4,top.mass=0.0512
"""
FIT_VARY = {"plate.murho": (-0.003, -0.0023)}


@pytest.fixture(scope="module")
def fit_data(tmp_path_factory):
    path = tmp_path_factory.mktemp("fit") / "heights.csv"
    path.write_text(FIT_CSV)
    return path


def test_fit_is_one_answer_for_the_api_and_the_command_line(study, fit_data, capsys):
    fit = study.fit(fit_data, FIT_VARY)
    assert type(fit) is Fit and lev.Fit is Fit and lev.FitResult is Fit
    out = _cli_json(capsys, "optimize", SCENE, "--fit", str(fit_data), "--vary", "plate.murho=-0.003:-0.0023")
    _same(out, cli._clean(fit.as_json()))
    assert out["scene"] == SCENE


def test_fit_residuals_hold_by_the_equilibrium_route(study, fit_data):
    """Each residual's model value is the hover height of the scene loaded at the fitted key with the
    row's overrides (Study.stability: the float equilibrium route, not the fit's CasADi one), and
    chi2 is the sum of the normalised residuals squared."""
    fit = study.fit(fit_data, FIT_VARY)
    murho = fit.parameters["plate.murho"]["value"]
    for r in fit.residuals:
        z = lev.load(SCENE, {"plate.murho": murho, **r["overrides"]}).stability().z_s
        assert r["model"] == pytest.approx(z, rel=1e-10)
        assert r["normalized"] == pytest.approx((z - r["value"]) / r["sigma"], rel=1e-6, abs=1e-9)
    assert fit.chi2 == pytest.approx(sum(r["normalized"] ** 2 for r in fit.residuals), rel=1e-12)
    assert fit.dof == 2 and fit.success


def test_stability_is_one_answer_for_the_api_and_the_command_line(study, capsys):
    """runtime/physics/stability/answer.py: `stability --json` is the answer's as_json(), which
    Study.stability() returns, the stiffness computed once, in the answer."""
    from levitron.runtime.physics.stability.answer import Stability
    st = study.stability()
    assert type(st) is Stability and lev.Stability is Stability and st.success
    _same(_cli_json(capsys, "stability", SCENE), cli._clean(st.as_json()), skip=("wall_s", "provenance",
                                                                                   "timings_s"))
    assert st.stiffness == pytest.approx(st.as_json()["stiffness"], rel=0) and st.stiffness > 0


def test_the_launch_odds_design_is_one_answer_for_the_api_and_the_command_line(tmp_path, capsys):
    """runtime/design/launch_design_answer.py: `optimize --maximize launch-odds --json` is the
    answer's as_json(), which Study.optimize("launch-odds", ...) returns for the same launches
    (n, seed, success_time, t_end), bit for bit; both write the same scene at the optimum."""
    from levitron.runtime.design.launch_design_answer import LaunchDesign
    launches = dict(n=40, seed=1, success_time=5.0, t_end=5.0)
    api = lev.load("thesis_air").optimize("launch-odds", {"top.mass": (0.0505, 0.0520)}, **launches)
    assert type(api) is LaunchDesign and lev.LaunchDesign is LaunchDesign and api.success
    r = _cli_json(capsys, "optimize", "thesis_air", "--maximize", "launch-odds", "--vary",
                  "top.mass=0.0505:0.052", "--n", "40", "--seed", "1", "--success-time", "5", "--t-end", "5",
                  "--write-scene", str(tmp_path / "cli.toml"))
    _same({k: r[k] for k in api.as_json()}, cli._clean(api.as_json()))
    api.write_scene(tmp_path / "api.toml")
    # the same scene but for its name, the file's stem
    assert (tmp_path / "api.toml").read_text() == (tmp_path / "cli.toml").read_text().replace(
        'name = "cli"', 'name = "api"')
    assert (tmp_path / "api.toml").read_text().startswith("# levitron optimize thesis_air --maximize launch-odds:")
    assert f"{100 * api.probability:.3g} %" in api.message
    assert repr(api).startswith("LaunchDesign(") and "success=True" in repr(api)
    with pytest.raises(lev.UserError, match="launch options go with maximize='launch-odds' or 'yield' only"):
        lev.load("thesis_air").optimize("spin-range", {"top.mass": (0.0505, 0.0520)}, n=40)


def test_the_height_fit_is_one_answer_for_the_api_and_the_command_line(capsys):
    """runtime/design/fit_height.py: `optimize --fit-height Z --json` is the answer's as_json(),
    which Study.fit_height(Z) returns; the fitted moment puts the top's equilibrium at Z, as the
    equilibrium finder sees it (thesis eq. 3.3.2: the thesis's lower height 7.62 cm)."""
    from levitron.runtime.design.fit_height import HeightFit
    fit = lev.load("thesis").fit_height(0.0762)
    assert type(fit) is HeightFit and lev.HeightFit is HeightFit and fit.success
    _same(_cli_json(capsys, "optimize", "thesis", "--fit-height", "0.0762"), cli._clean(fit.as_json()),
          skip=("wall_s", "provenance", "scene", "stats"))
    assert fit.param == "mu" and fit["optimum"]["mu"] == fit.value      # answer["key"]: its JSON's
    assert any(abs(e["z"] - 0.0762) <= 1e-8 for e in fit.equilibria) and abs(fit.residual_N) < 1e-10
    assert fit.message.startswith(f"fit: mu = {fit.value:.6g}, murho = ")
    assert "puts an equilibrium at 7.62 cm (vertically unstable)" in fit.message
    assert repr(fit) == f"HeightFit({fit.message.split('; ')[0]}; success=True)"
