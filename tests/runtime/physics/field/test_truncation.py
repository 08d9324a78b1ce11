"""An answer carries its truncation error: runtime/physics/field/truncation.py computes it at the field
expansion's order (thesis eqs. 2.2.4-2.2.7) and higher ones until it changes by less than 1 %.

The mechanism with a fake answer and fake models (no derivation: fast); thesis_stable's level
tolerance at order 2 (0.00165 rad, 15 % above the exact field's 0.00143 rad) raised to the order
where it converges, and a model already at a converged order kept (both derive: slow tier)."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.physics.field import truncation as tr
from levitron.runtime.words import render

ANNULUS = {"kind": "annulus", "radius": 0.1, "hole": 0.03, "murho": -0.0026}


def fake(order: int, plate: dict | None = None):
    """A stand-in model: its field order and its scene's plate table, all that the check reads."""
    return SimpleNamespace(manifest=SimpleNamespace(field_order=order),
                           scene=SimpleNamespace(data={"plate": plate or ANNULUS}))


def check(by_order: dict, n0: int = 2, **kw):
    """by_order: order -> the answer there; every order the check loads is recorded."""
    loaded = []

    def load(n):
        loaded.append(n)
        if isinstance(by_order.get(n), Exception):
            raise by_order[n]
        return fake(n)
    got = tr.by_order(fake(n0), lambda m: by_order[m.manifest.field_order], "the answer", "rad",
                      load=load, **kw)
    return got, loaded


def test_a_moving_answer_is_raised_to_the_order_where_it_converges_and_says_so():
    got, loaded = check({2: 1.65e-3, 4: 1.434e-3, 6: 1.4344e-3, 8: 1.0})
    assert loaded == [4, 6] and got.orders == (2, 4, 6) and got.order_used == 6
    assert got.value == 1.4344e-3 and got.raised and got.warning is None
    assert got.relative_differences[0] == pytest.approx((1.65e-3 - 1.434e-3) / 1.434e-3)
    assert got.relative_differences[1] < tr.RTOL
    assert got.line == got.note and "order 6's" in got.note and "‹0.0014344|rad›" in got.note
    assert "moves it by 15 %" in got.note         # from order 2 to the order used
    js = got.as_json()
    assert js["orders"] == [2, 4, 6] and js["order_used"] == 6 and js["values"][-1] == 1.4344e-3
    assert len(js["relative_difference"]) == 2 and js["warning"] is None


def test_an_answer_that_agrees_with_the_next_order_keeps_its_own_and_says_nothing():
    got, loaded = check({4: 2.0, 6: 2.0 * (1 + 0.5 * tr.RTOL)}, n0=4)
    assert loaded == [6] and got.orders == (4, 6) and got.order_used == 4 and got.value == 2.0
    assert not got.raised and got.line is None and got.warning is None and got.unchecked is None


def test_at_the_cap_a_moving_answer_warns_with_the_order_to_set():
    got, loaded = check({n: float(n) for n in range(2, 13, 2)})
    assert loaded == [4, 6, 8, 10] and got.order_used == tr.MAX_ORDER == 10
    assert got.note is None and got.line == got.warning
    assert "«set=field.order=12»" in got.warning
    assert "--set field.order=12" in render(got.warning, "cli")
    assert "overrides={'field.order': 12}" in render(got.warning, "api")


def test_above_the_scene_languages_orders_the_warning_names_the_exact_field():
    got, _ = check({n: float(n) for n in range(2, 13, 2)}, max_order=12)
    assert got.order_used == 12 and "«set" not in got.warning and "exact field" in got.warning


def test_a_higher_order_that_cannot_be_derived_is_said_not_raised():
    got, loaded = check({2: 1.0, 4: UserError("derive failed for scene 'x': boom")})
    assert loaded == [4] and got.orders == (2,) and got.order_used == 2 and got.value == 1.0
    assert "could not be derived" in got.unchecked and "boom" in got.note and got.warning is None
    # after one raise: the answer at the highest order reached, and the warning says why it stopped
    got, _ = check({2: 1.0, 4: 2.0, 6: UserError("no")})
    assert got.order_used == 4 and "order 6 could not be derived: no" in got.warning


def test_no_answer_at_one_order_is_a_difference_and_none_at_both_is_none():
    got, _ = check({2: None, 4: 0.5, 6: 0.5})
    assert got.relative_differences == (None, 0.0) and got.order_used == 6
    assert "none at field order 2" in got.note
    got, _ = check({2: None, 4: None})
    assert got.order_used == 2 and got.line is None


def test_an_exact_field_or_an_order_at_the_cap_tries_nothing():
    def never(n):
        raise AssertionError("loaded")
    square = {"kind": "rectangle", "side": 0.1, "thickness": 0.02, "remanence": 0.39}
    for model in (fake(4, square), fake(tr.MAX_ORDER), fake(12)):
        got = tr.by_order(model, lambda m: 1.0, "the answer", "rad", load=never)
        assert got.orders == (model.manifest.field_order,) and got.line is None and got.unchecked
    assert tr.expanded({**square, "hole": 0.01})
    assert not tr.expanded({"kind": "compound", "parts": [square]})
    assert tr.expanded({"kind": "compound", "parts": [square, ANNULUS]})


def test_each_order_is_announced_as_a_stage_before_its_answer():
    seen = []
    tr.by_order(fake(2), lambda m: seen.append(("answer", m.manifest.field_order)) or 1.0, "a", "rad",
                load=fake, stage=lambda n: seen.append(("stage", n)))
    assert seen == [("stage", 2), ("answer", 2), ("stage", 4), ("answer", 4)]


def test_the_plain_view_shows_the_truncation_warning_as_a_warning():
    from levitron.runtime.physics.stability.answer import Stability
    from levitron.runtime.physics.stability.view import note_lines
    from levitron.runtime.ui.human import Units
    r = {"notes": ["other", "it moves"], "level_tolerance": {"truncation": {"warning": "it moves"}}}
    assert note_lines(Stability.from_json(r), r["notes"], Units(si=True)) == ["other", "warning: it moves"]
    assert note_lines(Stability.from_json({}), ["x"], Units(si=True)) == ["x"]


# ---- on the real model (each order is derived once into the cache: slow tier)

MOMENT = ("plate.tilt=0", "top.moment_tilt=0")     # a tilted base's and a crooked magnet's terms


def test_thesis_stables_level_tolerance_is_raised_from_order_2_to_the_exact_fields(derived_model):
    """Order 2: 0.00165 rad; the exact field (and order 8) 0.00143 rad. The magnet's tolerance (by
    the relative equilibrium, about a second an order) does not move from order 2 to 4: kept."""
    from levitron.runtime.cli.commands.stability import human
    from levitron.runtime.physics.stability.answer import Stability
    model = derived_model("thesis_stable", *MOMENT)
    assert model.manifest.field_order == 2
    answer = Stability.of(model, level_tolerance=True)
    tol = answer.level_tolerance
    t = tol["truncation"]
    assert t["orders"][:2] == [2, 4] and t["order_used"] > 2 and t["values"][0] > 1.6e-3
    assert t["relative_difference"][0] > 0.1 and t["relative_difference"][-1] < tr.RTOL
    assert abs(tol["max_base_tilt"] - 1.43e-3) < 0.03 * 1.43e-3
    assert tol["max_base_tilt"] == t["values"][t["orders"].index(t["order_used"])]
    assert tol["fold_tilt"] is not None and tol["limited_by"] == "fold"
    assert answer._model.manifest.field_order == t["order_used"]     # the plot draws that model
    m = tol["moment_tolerance"]["truncation"]
    assert m["orders"] == [2, 4] and m["order_used"] == 2 and m["note"] is None and m["warning"] is None
    assert tol["max_moment_tilt"] == m["values"][0] and 0.2 < tol["max_moment_tilt"] < 0.3
    assert answer.notes[-1] == t["note"]
    text = render(human(answer.as_json(), model.scene), "cli")
    assert "the expansion about the axis (thesis eq. 2.2.6) cut at order 2 moves it by 15 %" in text
    assert "level to 0.0822 deg (0.001434 rad)" in text


def test_a_model_whose_next_order_agrees_keeps_its_answer(derived_model):
    """At order 4 thesis_stable's largest base tilt is order 6's to 1e-3: kept, nothing said."""
    from levitron.runtime.physics.apparatus.friction import without_friction
    from levitron.runtime.physics.apparatus.tilted_stability import level_tolerance
    model = derived_model("thesis_stable", *MOMENT, "field.order=4")

    def base_tilt(m):
        p = without_friction(m, m.p)
        return level_tolerance(m, m.with_params({"moment_tilt": 0.0}, p))["max_base_tilt"]
    got = tr.by_order(model, base_tilt, "the largest base tilt", "rad")
    assert got.orders == (4, 6) and got.order_used == 4 and got.line is None
    assert got.relative_differences[0] < 1e-3


def test_the_magnets_tolerance_by_shooting_stays_at_the_models_order_and_says_so(derived_model, monkeypatch):
    """Where the magnet's tolerance is shot (minutes an order) it is not computed again."""
    from levitron.runtime.physics.apparatus import rotating_equilibrium
    from levitron.runtime.physics.stability import answer as stability_answer
    from levitron.runtime.physics.apparatus import tilted_stability
    from levitron.runtime.physics.stability.answer import Stability
    monkeypatch.setattr(rotating_equilibrium, "refusal", lambda model, p: "the base is tilted")
    monkeypatch.setattr(tilted_stability, "level_tolerance", lambda model, p: {
        "max_base_tilt": 1e-3, "fold_tilt": 1e-3, "limited_by": "fold", "tilt_azimuth": 0.0})
    calls = []

    def moment(model, p):
        calls.append(model.manifest.field_order)
        return {"max_moment_tilt": 0.1, "moment_tolerance": {"how": "fake"}}
    monkeypatch.setattr(stability_answer, "_moment_tolerance", moment)
    answer = Stability.of(derived_model("thesis_stable", *MOMENT), level_tolerance=True)
    tol = answer.level_tolerance
    t = tol["moment_tolerance"]["truncation"]
    assert calls == [2] and t["orders"] == [2] and t["values"] == [0.1] and t["order_used"] == 2
    assert "shooting" in t["unchecked"] and "the base is tilted" in t["unchecked"] and t["note"] is None
    assert tol["moment_tolerance"]["how"] == "fake" and tol["max_moment_tilt"] == 0.1
    assert tol["truncation"]["orders"] == [2, 4] and tol["truncation"]["order_used"] == 2
