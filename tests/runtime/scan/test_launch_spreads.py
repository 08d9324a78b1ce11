"""Launch spreads say what they are (issue 26): the mass in kg or a relative spread spelt rel:...,
the shared launch request of launch / optimize --maximize launch-odds / trim, serial progress."""
from __future__ import annotations

import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan import launch_inputs as li


def test_an_absolute_mass_spread_is_the_mass_in_kg():
    d = mc.parse_input("mass", "normal:0.0515,0.0001", 0.0515)
    assert d.kind == "normal" and d.a == pytest.approx(0.0, abs=1e-15) and d.b == pytest.approx(0.0001 / 0.0515)
    u = mc.parse_input("mass", "uniform:0.05,0.053", 0.0515)
    assert (u.a, u.b) == pytest.approx((0.05 / 0.0515 - 1, 0.053 / 0.0515 - 1))


@pytest.mark.parametrize("spec, dist", [
    ("rel:normal:0,0.002", mc.Dist("normal", 0.0, 0.002)),
    ("rel:0.2%", mc.Dist("normal", 0.0, 0.002)),
    ("rel:uniform:-0.01,0.01", mc.Dist("uniform", -0.01, 0.01)),
    ("rel:-0.001", mc.Dist("fixed", -0.001)),
])
def test_a_relative_spread_says_so(spec, dist):
    got = mc.parse_input("mass", spec, 0.0515)
    assert got.kind == dist.kind and got.a == pytest.approx(dist.a) and got.b == pytest.approx(dist.b)


@pytest.mark.parametrize("name, spec", [("mass", "normal:0,0.002"), ("mass", "normal:0.2,0.001"),
                                        ("strength", "normal:0,0.005"), ("mass", "-1")])
def test_a_spread_in_the_wrong_form_is_refused_with_the_right_spelling(name, spec):
    with pytest.raises(UserError, match=r"rel:normal:0,0\.002 or «(mass|strength)» rel:0\.2%"):
        mc.parse_input(name, spec, 0.0515 if name == "mass" else 1.0)


@pytest.mark.parametrize("name", li.INPUTS)
def test_the_json_spec_reads_back_as_the_same_distribution(name):
    for d in (mc.Dist("normal", 0.1234567890123, 0.0098765432109876), mc.Dist("uniform", 0.001, 0.3),
              mc.Dist("fixed", 0.3333333333333333)):
        back = mc.parse_input(name, mc.spec_text(name, d))
        assert (back.kind, back.a, back.b) == (d.kind, d.a, d.b)


def test_the_request_refuses_inputs_that_are_not_a_mapping():
    with pytest.raises(UserError, match="must map input names"):
        mc.Request.of({}, "spin=1000")
    with pytest.raises(UserError, match="must map input names"):
        mc.Request.of({}, ["spin"])


def test_flags_win_over_the_table_over_the_defaults():
    r = mc.Request.of({"spin": "normal:900,10", "n": 7, "seed": 3}, {"tilt": "0.01"}, n=None, seed=4)
    assert r.n == 7 and r.seed == 4 and r.given == {"spin": "normal:900,10", "tilt": "0.01"}
    assert mc.Request.of({}).n == mc.DEFAULT_N


def test_a_serial_launch_goes_in_chunks_so_its_progress_moves(derived_model, monkeypatch):
    from levitron.runtime.scan import runners
    seen = []
    real = runners.run_serial

    def spy(plan, chunks, quiet=False, fn=None, what="scan"):
        seen.append(len(chunks))
        return real(plan, chunks, quiet, fn=fn, what=what)
    monkeypatch.setattr(runners, "run_serial", spy)
    model = derived_model("thesis_air")
    a = mc.Request({"tilt": "0.01"}, n=60, t_end=0.2).run(model, quiet=True)
    assert seen == [3]
    b = mc.Request({"tilt": "0.01"}, n=60, t_end=0.2, workers=2).run(model, quiet=True)
    assert a["verdicts"] == b["verdicts"] and a["flight_time"]["values"] == b["flight_time"]["values"]
