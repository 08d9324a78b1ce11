"""The fourth battery's classes, each tried once more with a case the first tests did not have
(/tmp notes of the closing note): the variants that did not hold before their fix.

  * paths as the user gave them: `--save` at a link of a loop of symbolic links (a.csv -> b.csv ->
    a.csv) replaced the link by a file; it is now one line, exit 2, the links kept
    (runtime/ui/atomic.py target);
  * one stop path: SIGTERM to a parallel `scan` ends it and its workers within seconds (held:
    tests/battery/test_stop.py test_a_parallel_scan_stops_with_its_workers);
  * every derivation bounded: a compound nested 400 deep was a RecursionError (exit 3) in the input
    hash's copy of the scene; 16 parts at field.order 12 (the parts budget's count, 112 s of
    derivation for annuli under load) passed: the nesting and the size budgets (scene/checks_budget.py).
"""
from __future__ import annotations

import os
import tomllib

import pytest

from levitron.scene.checks import SceneError
from levitron.scene.checks_budget import MAX_DEPTH, MAX_TERMS, field_terms
from levitron.scene.load import validate
from levitron.scene.plates.compound import MAX_PARTS
from tests.helpers.hostile import cli, refused


def test_save_at_a_loop_of_links_is_refused_and_keeps_the_links(tmp_path, warm_cache):
    os.symlink("b.csv", tmp_path / "a.csv")
    os.symlink("a.csv", tmp_path / "b.csv")
    res = cli(["scan", "thesis", "--set", "top.mass=0.0515", "--spin", "900:1500:2", "--tilt", "0.01:0.02:2",
               "--t-end", "0.05", "--workers", "1", "--save", "a.csv"], cwd=tmp_path,
              env={"LEVITRON_CACHE": str(warm_cache)}, timeout=120)
    refused(res, r"--save a\.csv: cannot write it \(Too many levels of symbolic links\)")
    assert os.readlink(tmp_path / "a.csv") == "b.csv" and os.readlink(tmp_path / "b.csv") == "a.csv"


def test_a_loop_of_links_is_no_target_in_the_api(tmp_path):
    from levitron.runtime.errors import UserError
    from levitron.runtime.ui import atomic
    os.symlink("b.txt", tmp_path / "a.txt")
    os.symlink("a.txt", tmp_path / "b.txt")
    with pytest.raises(UserError, match=r"^out .*a\.txt: cannot write it \(Too many levels of symbolic links\)"):
        atomic.write_text(tmp_path / "a.txt", "x", "out")
    assert (tmp_path / "a.txt").is_symlink()



# ---------------------------------------------------------------- every derivation bounded

def _ring(i: int) -> dict:
    return {"kind": "ring_magnet", "r_out": 0.05 + 0.001 * i, "r_in": 0.01, "thickness": 0.02, "remanence": 0.39}


def _scene(plate: dict, field: dict) -> dict:
    return {"name": "many", "top": {"mass": 0.02, "A": 1.32e-6, "C": 2.2e-6, "moment": -0.65}, "plate": plate,
            "field": field, "model": {"needs": ["reduced"]}}


def _nested(depth: int) -> dict:
    plate = _ring(0)
    for _ in range(depth):
        plate = {"kind": "compound", "parts": [plate]}
    return plate


def test_the_size_budget_is_the_parts_budget_at_order_2_and_shrinks_with_the_order():
    assert MAX_TERMS == MAX_PARTS * (2 + 3)
    many = {"kind": "compound", "parts": [_ring(i) for i in range(MAX_PARTS)]}
    assert validate(_scene(many, {"order": 2})).name == "many"
    with pytest.raises(SceneError) as exc:
        validate(_scene(many, {"order": 12}))
    msg = str(exc.value)
    assert "\n" not in msg, msg
    assert msg.startswith(f"the plate would derive {MAX_PARTS * 15} field terms ({MAX_PARTS} parts x "
                          f"(field.order 12 + 3)") and f"budget of {MAX_TERMS}: give at most 5 parts" in msg, msg
    five = {"kind": "compound", "parts": [_ring(i) for i in range(5)]}
    assert validate(_scene(five, {"order": 12})).name == "many"
    with pytest.raises(SceneError, match="would derive 90 field terms"):
        validate(_scene({"kind": "compound", "parts": [_ring(i) for i in range(6)]}, {"order": 12}))


def test_a_field_tolerance_is_counted_at_the_highest_order_it_may_choose():
    plate = {"kind": "compound", "parts": [_ring(i) for i in range(6)]}
    assert field_terms(plate, {"tolerance": 1e-3, "radius": 0.01}) == (90, 6, 12)
    with pytest.raises(SceneError, match="the highest order field.tolerance may choose 12"):
        validate(_scene(plate, {"tolerance": 1e-3, "radius": 0.01}))


def test_every_single_plate_kind_at_the_highest_order_is_inside_the_budget():
    from levitron.scene.plates import KINDS
    for name, kind in KINDS.items():
        table = tomllib.loads("[plate]\n" + kind.example)["plate"]
        terms, parts, _ = field_terms(table, {"order": 12})
        assert terms <= MAX_TERMS, (name, terms)


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 400, 5000])
def test_a_plate_nested_too_deep_is_one_line(depth):
    with pytest.raises(SceneError) as exc:
        validate(_scene(_nested(depth), {"order": 2}))
    assert str(exc.value).startswith(f"[plate] nests compounds more than {MAX_DEPTH} levels deep"), exc.value


def test_a_plate_nested_to_the_budget_is_taken():
    assert validate(_scene(_nested(MAX_DEPTH), {"order": 2})).name == "many"


@pytest.mark.parametrize("value", ["nan", '"normal:nan,10"', '"sometimes"'])
def test_a_bad_spread_in_the_launch_table_is_refused_as_the_tables(tmp_path, value):
    """Words that match what the user typed: a [launch] value is named as the table's, with the
    table's spelling as the fix, never a flag the user did not type."""
    from levitron.runtime.errors import UserError
    from levitron.runtime.scan.launch_odds import table_settings
    from levitron.runtime.words import render
    scene = tomllib.loads(f"[launch]\nspin = {value}\n")
    with pytest.raises(UserError) as exc:
        table_settings(scene["launch"])
    words = render(str(exc.value), "cli")
    assert words.startswith("[launch] spin = ") and "in the scene's [launch] table" in words
    assert "--spin" not in words and "«" not in str(exc.value)


def test_a_top_whose_moment_offset_puts_it_outside_its_box_is_told_so():
    """A magnet far above the centre of mass (top.moment_offset = -6 cm) starts the top outside the
    box about its hover height: the refusal names the key, not an offset the user did not give."""
    import levitron as lev
    from levitron.runtime.errors import UserError
    study = lev.load("thesis_stable", {"top.moment_offset": -0.06})
    with pytest.raises(UserError) as exc:
        study.simulate(1000.0, t_end=0.1)
    assert "top.moment_offset" in str(exc.value) and "offset 0" not in str(exc.value)


def test_a_level_base_is_not_called_tilted():
    """A magnet far above the centre of mass (moment_offset = -z_s) has no stable spin: the reason
    speaks of the level base it is over, not of a base tilted by 0 rad."""
    import levitron as lev
    st = lev.load("thesis_stable", {"top.moment_offset": -0.10646745880103986}).stability()
    assert st.spin_interval is None and "on the level base" in st.reason and "tilted by 0" not in st.reason
