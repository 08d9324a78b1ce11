"""The second battery of hostile inputs: every case is exit 2 with one error line, through
the real entry point, with the checks of tests/helpers/battery.py run_case (no traceback, generated/
unchanged, nothing half-written in a fresh cache). Every case failed before its fix
(exit 0 with a changed or dropped input, exit 3, or a wrong reason) except the eight marked
"guard": refused before too, they keep the refusal (the two large grids now refused before the
grid is built, see tests/scene/test_inputs_shared.py for the timing).
"""
from __future__ import annotations

import pytest

from tests.helpers.battery import THESIS, Case, expression_scene, run_case

FIT = "optimize thesis_stable --fit {tmp}/d.csv --vary plate.murho=-0.003:-0.0023"


def csv_file(text: str):
    def setup(tmp, env, request):
        (tmp / "d.csv").write_text(text)
    return setup


def fit_case(case_id: str, text: str, mention: str) -> Case:
    return Case(f"fit-{case_id}", FIT, mention, setup=csv_file(text))


def nested_toml(tmp, env, request):
    (tmp / "deep.toml").write_text("deep = " + "[" * 5000 + "]" * 5000 + "\n" + THESIS)


def cache_symlink_loop(tmp, env, request):
    (tmp / "loop").symlink_to(tmp / "loop")
    env["LEVITRON_CACHE"] = str(tmp / "loop")


def long_name_scene(tmp, env, request):
    (tmp / "long.toml").write_text(THESIS.replace('name = "thesis"', f'name = "{"a" * 250}"'))


GOOD_CSV_HEAD = "quantity,value,sigma,overrides\n"

BATTERY_17 = [
    # --- --set values that lost input silently
    Case("set-newline-drops-rest", "info thesis --set 'top.mass=0.03\nplate.hole=0.05'", r"control character"),
    Case("set-carriage-return", "info thesis --set 'top.mass=0.03\r'", r"control character"),
    Case("set-nul-byte", "info thesis --set top.mass=0.03\x00", r"control character"),
    Case("set-unbalanced-quote", "info thesis --set 'reference.source=\"abc'", r"not a TOML value"),
    Case("set-stray-quote-in-word", "info thesis --set 'plate.kind=ann\"ulus'", r"not a TOML value"),
    Case("set-nested-array", "info thesis --set top.mass=" + "[" * 3000 + "]" * 3000, r"nested too deeply"),
    # --- scene files
    Case("toml-nested-5000", "info {tmp}/deep.toml", r"nested too deeply", setup=nested_toml),
    # --- formulas whose constants have no real double (exit 0 with NaN/inf/0 in the C before)
    Case("expr-asin-2", "info {scene}", r"phi0.*not a real number", toml=expression_scene("asin(2)*z")),
    Case("expr-acos-1.5", "info {scene}", r"phi0.*not a real number", toml=expression_scene("acos(1.5)+z")),
    Case("expr-cube-root-of-negative", "info {scene}", r"phi0.*not a real",
         toml=expression_scene("(-8)**(1/3)*z")),
    Case("expr-exp-1000", "info {scene}", r"phi0.*beyond the range", toml=expression_scene("exp(1000)*z")),
    Case("expr-exp-minus-1e6", "info {scene}", r"phi0.*below the range",
         toml=expression_scene("z**2*exp(-1e6)")),
    Case("expr-1e308-times-10", "info {scene}", r"phi0.*beyond the range", toml=expression_scene("1e308*10*z")),
    Case("expr-1e-400", "info {scene}", r"phi0.*below the range", toml=expression_scene("1e-400*z")),
    Case("expr-power-overflow", "info {scene}", r"phi0.*beyond the range",
         toml=expression_scene("z*(10**100)**4")),
    Case("expr-derivative-overflow", "info {scene}", r"phi0.*double", toml=expression_scene("1e306*z**90")),
    Case("expr-tower-of-exp", "info {scene}", r"phi0.*beyond the range",
         toml=expression_scene("z*exp(exp(exp(exp(9))))")),
    Case("expr-nan-everywhere-equilibrium", "equilibrium {scene}", r"phi0.*not finite",
         toml=expression_scene("sqrt(-1 - z**2)")),
    Case("expr-nan-everywhere-stability", "stability {scene}", r"phi0.*not finite",
         toml=expression_scene("sqrt(-1 - z**2)")),
    # --- messages that named the wrong cause
    Case("cache-symlink-loop", "stability thesis", r"symbolic link to nothing", setup=cache_symlink_loop),
    Case("scene-name-250-characters", "stability {tmp}/long.toml", r"250 characters long",
         setup=long_name_scene),
    # --- numbers of the commands
    Case("stability-height-inf", "stability thesis_stable --height inf", r"--height"),
    Case("field-at-1e308", "field thesis --at 0,0,1e308", r"--at.*nearer"),
    Case("field-at-minus-1e300", "field thesis --at=-1e300,0,0.1", r"--at.*nearer"),
    Case("scan-grid-1e9-by-1e9", "scan thesis_stable --spin 1:2:1000000000 --tilt 0:0.1:1000000000",  # guard
         r"too many"),
    Case("scan-axis-1e12", "scan thesis_stable --spin 1:2:1000000000000 --tilt 0:0.1:2", r"too many"),
    Case("scan-product-too-big", "scan thesis_stable --spin 1:2:2000 --tilt 0:0.1:2000", r"too many"),  # guard
    # --- fit CSVs that were read silently wrong, or crashed
    fit_case("extra-column", "quantity,value,sigma,temperature\nz_s,0.1,1e-4,20\n", r"unknown column"),
    fit_case("extra-fields", "quantity,value,sigma\nz_s,0.1,1e-4,20,30\n", r"fields for 3 columns"),
    fit_case("repeated-column", "quantity,value,sigma,value\nz_s,0.1,1e-4,0.2\n", r"appears twice"),
    fit_case("override-twice", GOOD_CSV_HEAD + "z_s,0.1,1e-4,top.mass=0.05;top.mass=0.06\n",
             r"given twice"),
    fit_case("override-nan", GOOD_CSV_HEAD + "z_s,0.1,1e-4,top.mass=nan\n", r"top\.mass"),  # guard
    fit_case("override-no-equals", GOOD_CSV_HEAD + "z_s,0.1,1e-4,top.mass\n", r"key=number"),  # guard
    fit_case("sigma-1e-320", "quantity,value,sigma\nz_s,0.1,1e-320\n", r"too small"),
    fit_case("sigma-negative", "quantity,value,sigma\nz_s,0.1,-1e-4\n", r"sigma.*positive"),
    fit_case("sigma-nan", "quantity,value,sigma\nz_s,0.1,nan\n", r"sigma.*finite"),
    fit_case("value-inf", "quantity,value,sigma\nz_s,inf,1e-4\n", r"value.*finite"),  # guard
    fit_case("unknown-quantity", "quantity,value,sigma\nheight,0.1,1e-4\n", r"quantity 'height'"),  # guard
    fit_case("no-rows", "quantity,value,sigma\n", r"no data rows"),  # guard
    fit_case("no-header", "z_s,0.1,1e-4\n", r"header"),  # guard
]


def test_battery_17_size():
    assert len(BATTERY_17) >= 40
    assert len({c.id for c in BATTERY_17}) == len(BATTERY_17)


@pytest.mark.parametrize("case", BATTERY_17, ids=[c.id for c in BATTERY_17])
def test_issue_17_input_is_one_line_and_exit_2(case, tmp_path, warm_cache, capsys, monkeypatch, request):
    run_case(case, tmp_path, warm_cache, capsys, monkeypatch, request)
