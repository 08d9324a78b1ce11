"""Design by the launch odds (runtime/design/launch_design.py, issue 26): a known answer, the other
objectives' cost in launches, the refusals."""
from __future__ import annotations

import json

import pytest

from levitron.runtime.cli.main import main
from levitron.runtime.design.launch_design import maximize_launch_odds, plateau_middle
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc

SPIN = 2000.0      # rad/s: inside thesis_stable's interval for masses from ~50.8 g to the largest
# a hand so steady that a launch floats exactly where linear theory holds the top at SPIN
STEADY = {"spin": repr(SPIN), "tilt": "0.002", "tilt_azimuth": "0", "offset": "0", "velocity": "0",
          "mass": "rel:0", "strength": "rel:0"}


def _edge(model, lo, hi, inside):
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if inside(mid) else (mid, hi)
    return 0.5 * (lo + hi)


def test_a_steady_hand_is_advised_the_middle_of_the_masses_that_hold_its_spin(derived_model):
    """Known answer: with no spread the odds are 1 where SPIN lies in the linear interval of the
    mass (thesis 3.3.11-3.3.16, by the exact route) and 0 elsewhere; the advice is the middle of
    that range of masses. Its lower end is where sigma_lo(m) = SPIN, its upper end the largest mass
    the plate holds (thesis 3.3.2)."""
    from levitron.runtime.physics.equilibrium.finder import equilibria_of
    from levitron.runtime.physics.stability.analysis import stability_of
    model = derived_model("thesis_stable")

    def holds(m):
        try:
            iv = stability_of(model, mass=m, eigen=False).spin_interval
        except UserError:
            return False
        return iv is not None and iv[0] < SPIN < iv[1]
    lo = _edge(model, 0.0504, 0.0515, lambda m: holds(m))
    hi = equilibria_of(model).max_mass
    res = maximize_launch_odds(model, [Vary("top.mass", 0.0504, 0.0530)],
                               mc.Request(STEADY, n=4, t_end=30.0))
    assert res.probability == 1.0 and res.start_launch_odds["probability"] == 1.0
    assert res.optimum["top.mass"] == pytest.approx(0.5 * (lo + hi), abs=0.03 * (hi - lo))


def test_the_middle_of_a_plateau():
    pts = [((0.0,), 0.2), ((1.0,), 0.9), ((2.0,), 0.9), ((3.0,), 0.9), ((4.0,), 0.1)]
    assert plateau_middle(pts) == (2.0,)
    assert plateau_middle([((0.0, 0.0), 1.0), ((1.0, 0.0), 1.0), ((9.0, 9.0), 0.0)]) in ((0.0, 0.0), (1.0, 0.0))


def test_minimizing_the_odds_is_refused_with_a_reason(capsys):
    assert main(["optimize", "thesis_stable", "--minimize", "launch-odds", "--vary", "top.mass=0.05:0.052"]) == 2
    assert "not a design goal" in capsys.readouterr().err


def test_an_absolute_mass_spread_with_a_varied_mass_is_refused(capsys):
    assert main(["optimize", "thesis_air", "--maximize", "launch-odds", "--vary", "top.mass=0.05:0.052",
                 "--mass", "normal:0.0515,0.0001"]) == 2
    assert "must be relative" in capsys.readouterr().err


def test_the_widest_spin_window_warns_what_it_costs_in_launches(capsys):
    """thesis_air: the spin-range optimum sits at the band's edge, where the hand launch falls."""
    argv = ["optimize", "thesis_air", "--maximize", "spin-range", "--vary", "top.mass=0.0505:0.0524",
            "--n", "40", "--t-end", "20", "--json"]
    assert main(argv) == 0
    r = json.loads(capsys.readouterr().out)
    p, q = r["launch_odds"]["probability"], r["launch_odds_optimum"]["launch_odds"]["probability"]
    assert p < 0.5 * q
    assert any("--maximize launch-odds gives" in w for w in r["warnings"])
    assert set(r["start_launch_odds"]) >= {"probability", "probability_ci95", "n", "seed"}


def test_the_launch_design_bench_runs_in_its_quick_mode(tmp_path, capsys):
    """`levitron bench thesis_air --kind launch-design --quick` writes its table and plot (the
    bench measures; this only checks that it runs)."""
    assert main(["bench", "thesis_air", "--kind", "launch-design", "--quick", "--out", str(tmp_path), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    row = r["rows"][0]
    assert row["n"] == 6 and row["evaluations"] >= 7 and row["wall_s"] > 0
    assert all((tmp_path / f).stat().st_size > 0 for f in ("launch_design.json", "launch_design.csv",
                                                           "launch_design.png"))


def test_a_design_on_two_workers_in_one_kept_pool_is_the_serial_design(derived_model):
    """Every Monte Carlo of a design runs in one kept pool of workers (runners.KeptPool), each worker
    loading each design's model once: the answer is the serial one, launch for launch."""
    model = derived_model("thesis_stable")
    box = [Vary("top.mass", 0.0504, 0.0530)]
    given = {**STEADY, "tilt": "uniform:0,0.02", "mass": "rel:0.2%"}
    serial = maximize_launch_odds(model, box, mc.Request(given, n=8, t_end=2.0))
    kept = maximize_launch_odds(model, box, mc.Request(given, n=8, t_end=2.0, workers=2))
    assert kept.optimum == serial.optimum and kept.launch_odds == serial.launch_odds
    assert [e["probability"] for e in kept.evaluations] == [e["probability"] for e in serial.evaluations]


def test_the_search_steps_no_finer_than_a_maker_sets_the_key(derived_model):
    """The zoom and the plateau's edges stop once a step would be finer than the key's tolerance
    (runtime/design/launch_design.py step 3): with a tolerance wider than the grid's cell the search
    is the grid alone (and the middle of its plateau); with a fine one it zooms and bisects, and
    both advise a mass inside the other's tolerance of the answer."""
    model = derived_model("thesis_stable")
    box = [Vary("top.mass", 0.0504, 0.0530)]
    request = mc.Request(STEADY, n=4, t_end=30.0)
    coarse = maximize_launch_odds(model, box, request, tolerance={"top.mass": 0.0005})
    fine = maximize_launch_odds(model, box, request, tolerance={"top.mass": 1e-6})
    cell = (0.0530 - 0.0504) / 6
    assert coarse.work["evaluations"] <= 8 < fine.work["evaluations"]
    masses = sorted(row["top.mass"] for row in coarse.evaluations)
    assert min(b - a for a, b in zip(masses, masses[1:])) >= 0.5 * cell * (1 - 1e-9)   # the grid and its middle
    assert abs(coarse.optimum["top.mass"] - fine.optimum["top.mass"]) <= 0.0005


def test_the_search_says_when_it_judged_its_launches(derived_model):
    """The search ranks its designs at its search time, before the success time: its best odds are
    not the answer's, and the plain view says when they were judged (the JSON's search_time)."""
    model = derived_model("thesis_stable")
    res = maximize_launch_odds(model, [Vary("top.mass", 0.0512, 0.0518)], mc.Request(STEADY, n=4, t_end=30.0))
    t = res.as_json()["search"]["search_time"]
    assert 0 < t < res.success_time == 30.0
    assert f"judged at {t:.3g} s of the 30 s flight (to rank them, not for their odds)" in res.message
