"""Property-based tests (Hypothesis): the suite looks for bad inputs by itself.

Generated inputs, each through the in-process function the CLI and the API call:
  * scenes whose numbers sit at the edges (0, -0, denormals, 1e308, NaN, inf, huge integers,
    bools, text): validate() resolves finite parameters or raises a one-line SceneError; a valid
    scene's model (the thesis's, its numbers being runtime parameters) gives finite fields that
    agree between C and CasADi to 1e-12 of the size of the terms;
  * formula plates from a small grammar (constants of every magnitude, nesting, functions at their
    domain edges): derive's parser, plate builder, lowering, C printer and CasADi builder either
    refuse in one line (SceneError) or print a model; the printed ones are compiled together at the
    end (one compiler call) and C must equal CasADi wherever CasADi is finite;
  * --set values with quotes, backslashes and newlines: refused in one line or read back exactly;
    the API's writer round-trips every text;
  * fit CSVs: read into checked rows or refused in one line;
  * launch temperature spreads, fixed temperatures and [launch] tables: refused in one line or
    every draw a temperature the scene reader takes (the same verdict as --temperature); --save
    paths: refused in one line or one whole file that reads back, no temporary left.
Never another exception type, never a message of more than one line, and nothing written
outside the cache: every example runs in `confined()`, in a fresh empty working directory with
TMPDIR (and Python's tempfile) pointed at a fresh empty folder, and afterwards both must be empty
and the repository's tree (every file and folder, with its size and mtime; .git, .venv and
caches aside) unchanged.

Profiles: the default (CI) runs 230 examples derandomized (the same ones every run, under a
minute); `make fuzz` sets HYPOTHESIS_PROFILE=fuzz: 20 times as many, random, no deadline.
"""
from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import functools
import math
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, event, example, given, settings
from hypothesis import strategies as st

from levitron.derive.build import render  # noqa: F401  (imports the derive side once, outside the timing)
from levitron.derive.doubles import DoubleRangeError
from levitron.derive.expr_parse import ExpressionError
from levitron.scene.load import SceneError, load_scene, validate
from levitron.scene.overrides import override_text, parse_override
from levitron.runtime.design import measurements
from levitron.runtime.errors import UserError
from tests.helpers.termsize import assert_agree, values_and_sizes

FUZZ = os.environ.get("HYPOTHESIS_PROFILE") == "fuzz"


def budget(n: int):
    """n examples in CI (derandomized), 20 n random ones under `make fuzz`."""
    return settings(max_examples=n * (20 if FUZZ else 1), derandomize=not FUZZ, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
                    database=None)


ROOT = Path(__file__).resolve().parents[2]
NOT_TRACKED = {".git", ".venv", "__pycache__", ".pytest_cache", ".hypothesis", ".ruff_cache",
               "levitron.egg-info"}
CONFINED = {"examples": 0}
WATCHED = {"root": ROOT}     # the tree `confined()` snapshots (the probe test points it elsewhere)


def repo_tree() -> dict[str, tuple]:
    """Every file and folder under the repository (NOT_TRACKED and the cache aside, which may sit
    inside it: CI's is .cache-ci): path -> (size, mtime)."""
    from levitron.runtime.model.cbuild import resolve_cache_env
    cache = os.path.realpath(resolve_cache_env())
    out = {}
    for folder, dirs, files in os.walk(WATCHED["root"]):
        dirs[:] = [d for d in dirs if d not in NOT_TRACKED
                   and os.path.realpath(os.path.join(folder, d)) != cache]
        for name in dirs + files:
            st = os.lstat(os.path.join(folder, name))
            out[os.path.join(folder, name)] = (st.st_size, st.st_mtime_ns)
    return out


@contextlib.contextmanager
def confined():
    """Run the block in a fresh empty working directory with a fresh empty TMPDIR; afterwards
    both must be empty and the repository unchanged: nothing is written outside the cache."""
    before = repo_tree()
    cwd, tmp_env, tmp_py = os.getcwd(), os.environ.get("TMPDIR"), tempfile.tempdir
    with tempfile.TemporaryDirectory(prefix="levitron-confined-") as box:
        work, tmp = Path(box, "cwd"), Path(box, "tmp")
        work.mkdir()
        tmp.mkdir()
        os.chdir(work)
        os.environ["TMPDIR"], tempfile.tempdir = str(tmp), str(tmp)
        try:
            yield
        finally:
            os.chdir(cwd)
            tempfile.tempdir = tmp_py
            if tmp_env is None:
                os.environ.pop("TMPDIR", None)
            else:
                os.environ["TMPDIR"] = tmp_env
        assert not list(work.iterdir()), f"written into the working directory: {list(work.iterdir())}"
        assert not list(tmp.iterdir()), f"written into TMPDIR: {list(tmp.iterdir())}"
    after = repo_tree()
    changed = sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))
    assert not changed, f"written into the repository: {changed[:5]}"
    CONFINED["examples"] += 1


def each_confined(test):
    """The test body (one Hypothesis example per call) run in `confined()`."""
    @functools.wraps(test)
    def run(*args, **kwargs):
        with confined():
            return test(*args, **kwargs)
    return run


def one_line(exc: BaseException) -> None:
    msg = str(exc)
    assert msg and "\n" not in msg and "Traceback" not in msg, repr(msg)


EDGE_FLOATS = st.sampled_from([0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1e-308,
                               1e-12, 1e12, 1e308, -1e308, 1.7976931348623157e308, math.nan,
                               math.inf, -math.inf])
NUMBERS = st.one_of(EDGE_FLOATS, st.floats(allow_nan=True, allow_infinity=True),
                    st.floats(min_value=1e-6, max_value=1.0), st.integers(-10, 10),
                    st.just(10 ** 400), st.booleans(), st.text(max_size=5))


# ---------------------------------------------------------------- scenes with edge numbers

THESIS = load_scene("thesis").data


@budget(60)
@given(changes=st.dictionaries(st.sampled_from([("top", "mass"), ("top", "A"), ("top", "C"),
                                                ("plate", "radius"), ("plate", "hole"),
                                                ("plate", "murho"), ("", "g")]),
                               st.one_of(st.tuples(st.just("scale"), st.floats(0.8, 1.25)),
                                         st.tuples(st.just("set"), NUMBERS)),
                               min_size=1, max_size=3))
@each_confined
def test_scenes_with_edge_numbers(changes, thesis_model):
    data = {k: (dict(v) if isinstance(v, dict) else v) for k, v in THESIS.items()}
    data["top"].pop("moment", None)
    for (section, key), (how, value) in changes.items():
        table = data[section] if section else data
        table[key] = table[key] * value if how == "scale" else value
    try:
        scene = validate(data)
    except SceneError as exc:
        one_line(exc)
        event("scene refused")
        return
    event("scene valid: C vs CasADi compared")
    assert all(math.isfinite(v) for v in scene.params.values()), scene.params
    p = np.array([scene.params[n] for n in thesis_model.param_names])
    L = scene.length_scale
    X = np.array([[0.0, 0.1 * L, 0.3 * L], [0.0, 0.0, 0.05 * L], [0.5 * L, 1.0 * L, 2.0 * L]])
    P = np.tile(p[:, None], (1, X.shape[1]))
    fn = thesis_model.casadi("field")
    ca_out = np.asarray(fn(X, P), dtype=float)
    c_out = np.array([thesis_model.call("field", X[:, j], p) for j in range(X.shape[1])]).T
    assert np.isfinite(ca_out).all() and np.isfinite(c_out).all(), (scene.params, c_out)
    _, size = values_and_sizes(fn, X, P)
    assert_agree("field", c_out, ca_out, size)


# ---------------------------------------------------------------- formula plates from a grammar

CONSTANTS = st.sampled_from(["0", "1", "2", "3", "0.5", "1e-320", "1e-300", "1e-12", "7", "1e20",
                             "2**64", "2**63", "1e150", "1e300", "1e308", "(1/3)", "pi", "E"])
LEAVES = st.one_of(st.sampled_from(["z", "z", "b", "c"]), CONSTANTS)
FUNCS = ["sqrt", "exp", "log", "sin", "cos", "tan", "atan", "asin", "acos", "sinh", "cosh", "tanh",
         "asinh", "acosh", "atanh"]


def _combine(children):
    unary = st.tuples(st.sampled_from(FUNCS), children).map(lambda t: f"{t[0]}({t[1]})")
    binary = st.tuples(children, st.sampled_from(["+", "-", "*", "/"]), children).map(
        lambda t: f"({t[0]} {t[1]} {t[2]})")
    power = st.tuples(children, st.sampled_from(["2", "3", "-1", "(1/2)", "(-3/2)", "10"])).map(
        lambda t: f"({t[0]})**{t[1]}")
    edge = st.sampled_from(["asin(1)", "acos(-1)", "acosh(1)", "log(1)", "atanh(0)", "sqrt(0)",
                            "log(0)", "atanh(1)", "tan(pi/2)"])
    return st.one_of(unary, binary, power, edge)


FORMULAS = st.recursive(LEAVES, _combine, max_leaves=6)
PRINTED: list = []          # (table, params, lowered) of the plates that printed: compiled below
MAX_PRINTED = 80


@budget(60)
@given(formula=FORMULAS, key=st.sampled_from(["phi0", "phi0", "phi0", "bz"]))
@each_confined
def test_formula_plates_refuse_in_one_line_or_print(formula, key):
    from levitron.derive.emit.c.emitter import body_lines
    from levitron.derive.emit.c.printer import LevitronCPrinter
    from levitron.derive.emit.casadi.builder import build_function
    from levitron.derive.emit.lower import lower
    from levitron.derive.geometry import build_plate
    from levitron.derive.spec import build_spec
    from levitron.derive.plate_fields import expression as symbolic
    table = {"kind": "expression", key: formula, "params": {"b": 1.3, "c": 0.7}}
    budget_s, symbolic.TIME_BUDGET_S = symbolic.TIME_BUDGET_S, 5.0   # a slow formula: its refusal
    try:
        spec = build_spec("f", build_plate(table), 2, "tait-bryan", [])
        lowered = [lower(f, spec) for f in spec.functions]
        printer = LevitronCPrinter()
        for low in lowered:
            body_lines(low, printer)
            build_function(low, len(spec.params))
    except (SceneError, DoubleRangeError) as exc:
        # DoubleRangeError: a constant of a derivative no double holds (z*(z*1e308): 2e308), found
        # by the C printer; derive.build.render turns it into the SceneError naming the formula
        one_line(exc)
        event("formula refused")
        return
    except ExpressionError as exc:          # raised by the parser; derive wraps it as SceneError
        pytest.fail(f"{formula!r}: an ExpressionError escaped the plate builder: {exc}")
    finally:
        symbolic.TIME_BUDGET_S = budget_s
    event("formula printed")
    if len(PRINTED) < MAX_PRINTED:
        PRINTED.append((table, [str(s) for s in spec.params], lowered))


def test_printed_formula_plates_compute_the_same_in_c_and_casadi(tmp_path):
    """The plates the grammar test printed, compiled together: C equals CasADi where it is finite."""
    from levitron.derive.emit.c.emitter import body_lines
    from levitron.derive.emit.c.printer import FMA_PRELUDE, LevitronCPrinter
    from levitron.derive.emit.casadi.builder import build_function
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compile_shared
    if not PRINTED:
        pytest.skip("run with test_formula_plates_refuse_in_one_line_or_print (it fills PRINTED)")
    assert len(PRINTED) >= 10, f"only {len(PRINTED)} formulas printed: the grammar is too hostile"
    printer = LevitronCPrinter()
    src = [FMA_PRELUDE, "#ifndef M_PI", "#define M_PI 3.14159265358979323846", "#endif"]
    cases = []
    for i, (table, params, lowered) in enumerate(PRINTED):
        for low in lowered:
            name = f"g{i}_{low.name}"
            lines = [f"void {name}(const double *in, const double *p, double *out)", "{",
                     "    (void)in; (void)p;"]
            lines += [f"    const double {v} = in[{k}];" for k, v in low.inputs]
            lines += [f"    const double {v} = p[{k}];" for k, v in low.params]
            lines += [f"    {ln}" for ln in body_lines(low, printer)]
            src.append("\n".join(lines + ["}"]))
            cases.append((table, name, low, params,
                          build_function(dataclasses.replace(low, name=name), len(params))))
    path = tmp_path / "grammar.c"
    path.write_text("\n\n".join(src) + "\n")
    with confined():                  # the compiler's temporaries in TMPDIR, its library in the cache
        lib = ctypes.CDLL(str(compile_shared([path], DEFAULT_FLAGS)))
    dbl = ctypes.POINTER(ctypes.c_double)
    rng = np.random.default_rng(17)
    compared = 0
    for table, name, low, params, fn in cases:
        n_in = low.n_in
        X = np.vstack([rng.uniform(-0.3, 0.3, (n_in - 1, 16)), rng.uniform(0.1, 3.0, (1, 16))])
        pv = {"m": 0.02, "g": 9.81, "A": 2.2e-6, "C": 1.32e-6, "mu": -1.0, "plate_b": 1.3, "plate_c": 0.7}
        p = np.array([pv[n] for n in params])
        P = np.tile(p[:, None], (1, X.shape[1]))
        with np.errstate(all="ignore"):
            ca_out = np.asarray(fn(X, P), dtype=float)
            _, size = values_and_sizes(fn, X, P)
        c_out = np.empty_like(ca_out)
        for j in range(X.shape[1]):
            x = np.ascontiguousarray(X[:, j])
            out = np.empty(ca_out.shape[0])
            getattr(lib, name)(x.ctypes.data_as(dbl), p.ctypes.data_as(dbl), out.ctypes.data_as(dbl))
            c_out[:, j] = out
        keep = np.isfinite(ca_out).all(axis=0) & np.isfinite(size).all(axis=0)
        if keep.any():
            compared += 1
            assert_agree(f"{table} {low.name}", c_out[:, keep], ca_out[:, keep], size[:, keep])
    assert compared >= len(cases) // 3, f"only {compared} of {len(cases)} functions had finite points"


# ---------------------------------------------------------------- --set values

TEXTS = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=30)
QUOTY = st.text(alphabet=st.sampled_from(list("ab \"'\\\n\r\t=#[]{}.,0123456789e-+")), max_size=20)


@budget(40)
@given(value=st.one_of(TEXTS, QUOTY))
@each_confined
def test_set_values_are_refused_in_one_line_or_read_exactly(value):
    try:
        keys, got = parse_override(f"reference.source={value}")
    except SceneError as exc:
        one_line(exc)
        return
    assert keys == ["reference", "source"]
    assert not any(ch in value for ch in "\n\r\x00"), "a control character got through"
    if isinstance(got, str) and not value.strip().startswith(("\"", "'")):
        assert got == value.strip()           # a bare word is taken as written


@budget(40)
@given(value=st.one_of(TEXTS, QUOTY, st.floats(allow_nan=False), st.integers(-10 ** 6, 10 ** 6),
                       st.booleans(), st.lists(st.one_of(QUOTY, st.integers()), max_size=4)))
@each_confined
def test_the_api_writer_round_trips_every_value(value):
    text = override_text("reference.source", value)
    assert "\n" not in text and "\r" not in text
    assert parse_override(text) == (["reference", "source"], value)


# ---------------------------------------------------------------- fit CSVs

CELLS = st.one_of(st.sampled_from(["z_s", "stiffness", "sigma_lo", "height", "", "0.1", "1e-4",
                                   "-1e-4", "0", "nan", "inf", "1e-320", "1e308", "top.mass=0.05",
                                   "top.mass=0.05;top.mass=0.06", "top.mass=nan", "a=b", "\"q\""]),
                  st.floats().map(repr), QUOTY.filter(lambda s: "\n" not in s and "\r" not in s))
HEADERS = st.sampled_from(["quantity,value,sigma", "quantity,value,sigma,overrides",
                           "quantity,value,sigma,extra", "value,quantity,sigma", "quantity,value",
                           "quantity,value,sigma,sigma", ""])


@budget(30)
@given(header=HEADERS, rows=st.lists(st.lists(CELLS, min_size=2, max_size=5), max_size=4))
def test_fit_csvs_are_read_checked_or_refused_in_one_line(header, rows, tmp_path_factory):
    path = tmp_path_factory.mktemp("csv") / "d.csv"
    path.write_text(header + "\n" + "\n".join(",".join(r) for r in rows) + "\n")
    try:
        with confined():
            got = measurements.read_rows(path)
    except UserError as exc:
        one_line(exc)
        return
    assume(got)
    for r in got:
        assert r.quantity in measurements.QUANTITIES and math.isfinite(r.value)
        assert math.isfinite(r.sigma) and r.sigma >= measurements.MIN_SIGMA
        keys = [k for k, _ in r.overrides]
        assert len(keys) == len(set(keys)) and all(math.isfinite(v) for _, v in r.overrides)


# ---------------------------------------------------------------- spreads, [launch] tables, temperatures, --save paths

AIR_DATA = load_scene("thesis_air").data
SPREAD_NUMBERS = st.one_of(EDGE_FLOATS, st.floats(-400, 1600), st.integers(-300, 2000), st.text(max_size=4))
SPREADS = st.one_of(
    st.builds(lambda a, b: f"normal:{a},{b}", SPREAD_NUMBERS, SPREAD_NUMBERS),
    st.builds(lambda a, b: f"uniform:{a},{b}", SPREAD_NUMBERS, SPREAD_NUMBERS),
    SPREAD_NUMBERS.map(str), NUMBERS, QUOTY)


@budget(60)
@given(spec=SPREADS)
@example(spec="uniform:0.0,-0.0")     # a range of one point written as -0.0: numpy's uniform refused it
@each_confined
def test_a_temperature_spread_is_refused_or_every_draw_is_a_temperature(spec):
    """A launch temperature spread through monte_carlo's checks (launch_odds.parse_input, then
    validate.spread_range and validate.temperature): refused in one line, or each of 2000 draws
    is a temperature the scene reader takes (scene/load.py temperature_factors, the second route)."""
    from levitron.scene.load import temperature_factors
    from levitron.runtime.scan import launch_odds as mc
    from levitron.runtime.ui.validate import spread_range, temperature
    try:
        d = mc.parse_input("temperature", spec)
        temperature(AIR_DATA, *spread_range(d.kind, d.a, d.b)[:2], "--temperature-spread")
    except UserError as exc:
        one_line(exc)
        event("refused")
        return
    event("taken")
    for T in d.sample(np.random.Generator(np.random.PCG64(0)), 2000):
        assert min(temperature_factors({**AIR_DATA, "temperature": float(T)})) > 0


@budget(40)
@given(T=st.one_of(EDGE_FLOATS, st.floats(-400, 2000), st.integers(-400, 2000)))
@each_confined
def test_one_temperature_check_for_the_scene_and_the_spread(T):
    """A fixed temperature is taken by the launch check exactly when the scene takes it as
    `--temperature` (one validation per quantity)."""
    from levitron.runtime.ui.validate import temperature
    try:
        load_scene("thesis_air", [override_text("temperature", T)])
        scene_ok = True
    except SceneError:
        scene_ok = False
    try:
        temperature(AIR_DATA, T, T, "--temperature-spread")
        spread_ok = True
    except UserError as exc:
        one_line(exc)
        spread_ok = False
    assert scene_ok == spread_ok, T


TABLE_KEYS = st.sampled_from(["n", "seed", "success_time", "t_end", "spin", "temperature", "mass", "tilt"])


@budget(40)
@given(table=st.dictionaries(TABLE_KEYS, st.one_of(NUMBERS, SPREADS), max_size=5))
@each_confined
def test_launch_tables_are_read_checked_or_refused_in_one_line(table):
    """A [launch] table (launch_odds.table_settings, as the CLI and the API read it): refused in
    one line, or n and seed whole numbers in range and the times positive and finite."""
    from levitron.runtime.scan import launch_odds as mc
    try:
        inputs, settings_ = mc.table_settings(table)
        for name, spec in inputs.items():
            mc.parse_input(name, spec, AIR_DATA["top"]["mass"] if name == "mass" else 1.0)
    except UserError as exc:
        one_line(exc)
        event("refused")
        return
    event("taken")
    assert set(inputs) | set(settings_) == set(table)
    assert 1 <= settings_.get("n", 1) <= mc.MAX_N and settings_.get("seed", 0) >= 0
    assert all(math.isfinite(settings_[k]) and settings_[k] > 0 for k in ("success_time", "t_end")
               if k in settings_)


SAVE_NAMES = st.one_of(QUOTY.filter(lambda s: "/" not in s and "\x00" not in s),
                       st.text(alphabet=st.characters(blacklist_categories=("Cs",), blacklist_characters="/\x00"),
                               max_size=12))


@budget(40)
@given(stem=SAVE_NAMES, suffix=st.sampled_from([".csv", ".npz", ".CSV", ".NPZ", ".txt", "", ".csv.tmp"]))
def test_save_paths_are_written_whole_or_refused_in_one_line(stem, suffix, tmp_path_factory):
    """A --save / Simulation.save path (runtime/simulate/trajectory_file.py through runtime/ui/atomic.py):
    refused in one line, or the one file is there, reads back equal, and no temporary is left."""
    from levitron.runtime.simulate import trajectory_file
    folder = tmp_path_factory.mktemp("save")
    table = np.linspace(0.0, 1.0, 12).reshape(4, 3)
    try:
        with confined():
            path = trajectory_file.write(folder / f"{stem}{suffix}", ["t", "x", "y"], table)
    except UserError as exc:
        one_line(exc)
        assert list(folder.iterdir()) == []
        event("refused")
        return
    event("written")
    assert list(folder.iterdir()) == [path]
    names, back = trajectory_file.read(path)
    assert names == ["t", "x", "y"] and np.array_equal(back, table)


def test_every_example_ran_confined():
    """The examples above ran in `confined()` (run last in this module, in file order)."""
    if CONFINED["examples"] == 0:
        pytest.skip("run with the property tests above")
    assert CONFINED["examples"] >= 1


def test_confined_sees_a_stray_file_wherever_it_is_written(tmp_path, monkeypatch):
    """`confined()` fails on a file left in the working directory, in TMPDIR or in the repository
    (here a copy of its tests/ folder: a stray in the real one would fail the confined examples
    another xdist worker runs at the same moment)."""
    with pytest.raises(AssertionError, match="working directory"):
        with confined():
            Path("stray.txt").write_text("x")
    with pytest.raises(AssertionError, match="TMPDIR"):
        with confined():
            tempfile.mkstemp()
    shutil.copytree(ROOT / "tests", tmp_path / "repo" / "tests", ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setitem(WATCHED, "root", tmp_path / "repo")
    probe = tmp_path / "repo" / "tests" / ".confined-probe"
    try:
        with pytest.raises(AssertionError, match="repository"):
            with confined():
                probe.write_text("x")
    finally:
        probe.unlink(missing_ok=True)
