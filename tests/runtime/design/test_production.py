"""The yield of a production run (runtime/design/production.py): a run whose kits all float after
trim, one no washer can help, the owner's choice, and the checks of a production run."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from levitron.runtime.design import production as pr
from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc

# a hand so steady that a launch floats exactly where linear theory holds the top at 2000 rad/s
# (thesis_stable: from about 50.8 g to the heaviest mass the plate holds, about 52.49 g)
STEADY = {"spin": "2000.0", "tilt": "0.002", "tilt_azimuth": "0", "offset": "0", "velocity": "0",
          "mass": "rel:0", "strength": "rel:0"}
# magnets within +-1 %; washers of 0.4, 0.8 and 1.6 g add 0 to 2.8 g in steps of 0.4 g
KIT = {"strength": "rel:uniform:-0.01,0.01", "mass": "rel:0"}
WASHERS = (0.0004, 0.0008, 0.0016)


def _run(derived_model, mass: float, washers=WASHERS, kits: int = 24) -> dict:
    """The production run of a 50.5 g-pinned hand at a top of `mass` (a design point)."""
    pinned = derived_model("thesis_stable", "top.mass=0.0515")
    prep = mc.prepare(pinned, STEADY, kits, 0, t_end=3.0)
    here = derived_model("thesis_stable", f"top.mass={mass!r}")
    plan = replace(prep.plan, scene=here.ref[0], overrides=tuple(here.ref[1]))
    prod = pr.Production.of(KIT, washers, kits)
    return pr.production_yield(here, plan, prep.success_time, prep.success_time, prod)


def test_every_kit_floats_when_the_washers_reach_the_band_whatever_its_magnets(derived_model):
    """A 50.0 g top (below the masses that hover at the hand's spin) with magnets +-1 %: a kit of
    strength s hovers at equivalent mass (50 g + w) / s, and some washer total w puts every kit's
    inside [50.9, 52.3] g: every kit floats after trim, none as shipped."""
    r = _run(derived_model, 0.0500)
    assert r["yield"]["probability"] == 1.0 and r["yield"]["successes"] == 24
    assert r["as_shipped"]["probability"] == 0.0
    assert r["untrimmable"] == 0.0 and r["washers_used"][0.0] == 0


def test_no_washer_helps_a_top_too_heavy_for_every_kit(derived_model):
    """A 53.5 g top is heavier than any kit's magnets hold (52.49 g x 1.01 at most), and washers only
    add: no kit floats, with or without them, and every kit is untrimmable."""
    r = _run(derived_model, 0.0535)
    assert r["yield"]["probability"] == r["as_shipped"]["probability"] == 0.0
    assert r["untrimmable"] == 1.0


def test_the_owner_takes_the_washers_whose_place_in_the_band_floats_best():
    """The position (m + w - lo_k) / (hi_k - lo_k) in the kit's band on the curve; ties go to the one
    nearest the curve's best; a kit of strength s has the band s [lo, hi]."""
    band = np.array([0.5, 3.5])
    curve = {"position": [(1.0 - 0.5) / 3, 0.5, (3.0 - 0.5) / 3], "odds": [0.0, 1.0, 1.0],
             "best_position": (2.8 - 0.5) / 3}
    totals = np.array([0.0, 1.0, 2.0])
    got = pr.owner_choice(curve, np.array([0.5, 1.0, 0.5]), np.outer([1.0, 1.0, 0.5], band), totals)
    # kit 1: 0.5 + w in {0.5, 1.5, 2.5}, odds {0, 0.5, 1}: w = 2; kit 2: {1, 2, 3}, odds {0, 1, 1},
    # the tie to 3 (nearest 2.8): w = 2; kit 3 (s = 0.5, band [0.25, 1.75]): 0.5 + w in
    # {0.5, 1.5, 2.5}, positions {1/6, 5/6, outside}: w = 1
    assert got.tolist() == [2.0, 2.0, 1.0]


def test_the_washers_add_each_subset_once():
    prod = pr.Production.of({}, (0.1, 0.2, 0.2))
    assert prod.totals().tolist() == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4, 0.5])


@pytest.mark.parametrize("kit, washers, kits, words", [
    ({"spin": "rel:1%"}, (), 300, "strength or mass"),
    ({"plate.hole": "normal:0.03,0.0001"}, (), 300, "deviation from the design"),
    ({"strength": "normal:1,0.02"}, (), 300, "relative"),
    ({}, (-0.001,), 300, "positive"),
    ({}, ("heavy",), 300, "not a mass"),
    ({}, (0.001,) * 9, 300, "at most 8"),
    ({}, (), 3, "from 10"),
])
def test_a_production_run_is_checked_in_one_line(kit, washers, kits, words):
    with pytest.raises(UserError) as err:
        pr.Production.of(kit, washers, kits)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_a_kit_launch_past_its_window_does_not_float(derived_model):
    """As in `launch` (runtime/scan/launch_window.py): a kit's launch still up at the success time
    whose spin has decayed below its window floats no more (thesis_air, 8 s decay time, 1750 rad/s:
    454 rad/s at 10.8 s, below 459.6); at 5 s its spin is twice the edge and the verdicts stand."""
    from levitron.runtime.design import production
    from levitron.runtime.scan import launch_odds as mc
    model = derived_model("thesis_air", "top.spin_decay_time=8")
    hand = {"spin": "normal:1750,1", "tilt": "uniform:0,0.002", "offset": "0", "velocity": "0"}
    for success_time, some in ((10.8, False), (5.0, True)):
        prep = mc.prepare(model, hand, n=8, success_time=success_time, workers=1)
        floats = production._verdicts(model, prep.plan, mc.samples(prep.plan), success_time, None)
        assert floats.any() == some


@pytest.mark.parametrize("kit", [KIT, {**KIT, "plate.hole": "abs:normal:0,0.0001"}], ids=["strength", "plate_key"])
def test_a_production_run_on_a_dask_scheduler_is_the_local_one(derived_model, kit, monkeypatch):
    """«scheduler» as launch takes it: the kits' launches (each at its own parameters where a scene
    key is spread) run on a real dask.distributed cluster and give the local run's verdicts."""
    distributed = pytest.importorskip("dask.distributed", reason="the test extra installs dask[distributed]")
    from levitron.runtime.scan import runners
    on_dask, real = [], runners.run_dask
    monkeypatch.setattr(runners, "run_dask", lambda *a, **k: on_dask.append(1) or real(*a, **k))
    pinned = derived_model("thesis_stable", "top.mass=0.0515")
    prep = mc.prepare(pinned, STEADY, 12, 0, t_end=1.0)
    prod = pr.Production.of(kit, WASHERS, 12)
    local = pr.production_yield(pinned, prep.plan, prep.success_time, prep.success_time, prod)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, host="127.0.0.1",
                                  protocol="tcp", dashboard_address=None) as cluster:
        remote = pr.production_yield(pinned, prep.plan, prep.success_time, prep.success_time, prod,
                                     scheduler=cluster.scheduler_address)
    assert on_dask and remote["verdicts"] == local["verdicts"] and remote["yield"] == local["yield"]


@pytest.mark.parametrize("table, words", [
    ({"kit": {"plate.radius": "abs:normal:0,-1"}}, "[production.kit] plate.radius"),
    ({"kit": {"strength": "normal:1,0.02"}}, "[production.kit] strength"),
    ({"washers": [-0.001]}, "[production] washers")])
def test_a_bad_value_of_the_production_table_is_refused_as_the_tables(table, words):
    """Words that match what the user typed: a value of the scene's [production] table is named as
    the table's, never as a flag the user did not type; the same value as a flag names the flag."""
    from levitron.runtime.words import render
    with pytest.raises(UserError) as exc:
        pr.Production.of(table=table)
    said = render(str(exc.value), "cli")
    assert said.startswith(words) and "--kit" not in said and "--washers" not in said
    if "kit" in table:
        with pytest.raises(UserError) as flag:
            pr.Production.of(kit=table["kit"], table=table)
        assert render(str(flag.value), "cli").startswith("--kit ")
