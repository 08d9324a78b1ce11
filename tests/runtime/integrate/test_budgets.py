"""Bounded work: one integrator table that the C library agrees with, and no integrator path without
a step budget (runtime/integrate/methods.py, runtime/integrate/budget.py)."""
from __future__ import annotations

import ctypes
import math

import numpy as np
import pytest

from levitron.runtime.integrate import c_backend as ci
from levitron.runtime.integrate import run as ig
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.methods import BY_NAME, METHODS, TABLE
from levitron.runtime.integrate.budget import MAX_STEPS_CAP, check_options, default_budget, step_cap

T_END = 1000.0     # 160 periods of the unit oscillator: far more than a budget of 3 steps covers


@pytest.fixture(scope="module")
def casadi_osc(lib):
    """The unit oscillator of tests/c/systems.c with a CasADi right-hand side for the casadi
    backend (scipy reaches it through ctypes)."""
    import casadi as ca

    class Osc(ci.CSystem):
        def casadi(self, name):
            x, p = ca.SX.sym("x", 4), ca.SX.sym("p", 1)
            return ca.Function("rhs", [x, p], [ca.vertcat(x[2], x[3], -p[0] * x[0], -p[0] * x[1])])

    return Osc(lib, "lev_oscillator", ["x", "y", "vx", "vy"], [1.0])


def test_c_method_table_equals_the_python_table(lib):
    c_entries = [e for e in TABLE if e.backend == "c"]
    for e in c_entries:
        assert lib.lev_method_id(e.name.encode()) == e.c_id, e.name
        assert lib.lev_method_fixed_step(e.c_id) == int(e.fixed_step), e.name
    ids = sorted(e.c_id for e in c_entries)
    assert ids == list(range(len(ids)))
    assert lib.lev_method_name(len(ids)) is None          # C knows no method the table lacks
    assert [lib.lev_method_name(i).decode() for i in ids] == [
        next(e.name for e in c_entries if e.c_id == i) for i in ids]
    assert lib.lev_method_id(b"leapfrog") == -1
    assert all(e.c_id is None for e in TABLE if e.backend != "c")
    assert {e.backend for e in TABLE} == {"c", "casadi", "scipy"}


def test_struct_sizes_equal_the_ctypes_mirrors(lib):
    for fn, struct in (("lev_sizeof_system", ci._System), ("lev_sizeof_options", ci._Options),
                       ("lev_sizeof_stats", ci._Stats), ("lev_sizeof_job", ci._Job)):
        f = getattr(lib, fn)
        f.restype = ctypes.c_size_t
        assert f() == ctypes.sizeof(struct), fn


def test_a_wrong_struct_mirror_is_refused():
    """bind compares every mirror with the library's sizeof before the first call."""
    class Fake:
        def __init__(self):
            self.lev_integrate = type("F", (), {"argtypes": None})()
            self.lev_sizeof_system = lambda: ctypes.sizeof(ci._System) + 8
    with pytest.raises(RuntimeError, match="_System"):
        ci.bind(Fake())


def test_every_table_entry_has_a_default_budget():
    for e in TABLE:
        h = 0.01 if e.fixed_step else None
        n = default_budget(e.name, 10.0, h, time_scale=1.0)
        assert 1 <= n <= step_cap(e.name) <= MAX_STEPS_CAP, e.name
        assert default_budget(e.name, 10.0, h, time_scale=None) <= step_cap(e.name)
        if not e.fixed_step:    # a run far longer than the time scale: the cap binds
            assert default_budget(e.name, 1e9, None, time_scale=1.0) == step_cap(e.name)


@pytest.mark.parametrize("method", METHODS)
def test_no_step_budget_free_integrator_path(casadi_osc, method):
    """Each integrator with a tiny budget stops with status "step_budget", quickly, and says so."""
    kw = {"h": 0.01} if BY_NAME[method].fixed_step else {"tol": 1e-10}
    r = ig.integrate(casadi_osc, [1.0, 0.0, 0.0, 1.0], T_END, method=method, n_out=1, max_steps=3,
                     scale=[1, 1, 1, 1], **kw)
    assert r.status == "step_budget", (method, r.status, r.message)
    assert "step budget of 3 steps" in r.message
    assert r.t_final < T_END and np.all(np.isfinite(r.x_final))
    if r.steps:
        assert r.steps <= 3


@pytest.mark.parametrize("method", ["dop853", "rk4", "scipy-dop853", "cvodes", "casadi-rk"])
def test_default_budget_lets_a_normal_run_finish(casadi_osc, method):
    kw = {"h": 0.01} if BY_NAME[method].fixed_step else {"tol": 1e-10}
    r = ig.integrate(casadi_osc, [1.0, 0.0, 0.0, 1.0], 2 * math.pi, method=method, n_out=10,
                     scale=[1, 1, 1, 1], time_scale=2 * math.pi, **kw)
    assert r.status == "completed", (method, r.message)
    assert np.abs(r.x_final - [1.0, 0.0, 0.0, 1.0]).max() < 1e-6


@pytest.mark.parametrize("kwargs, words, param", [
    ({"method": "dop853", "tol": 1.0}, "too loose", "tol"),
    ({"method": "dop853", "tol": 0.0}, "positive", "tol"),
    ({"method": "dop853", "tol": 1e-16}, "double precision", "tol"),
    ({"method": "rk4", "h": 1e-12}, "below 1e-09", "step"),
    ({"method": "rk4", "h": 2.0}, "cannot resolve", "step"),
    ({"method": "rk4", "h": 1e-6, "t_end": 1e5}, "budget cap", "t_end"),
    ({"method": "dop853", "tol": 1e-9, "t_end": 1e9}, "spans .* above the budget cap", "t_end"),
    ({"method": "dop853", "tol": 1e-9, "time_scale": 1e-14}, "resolves", "t_end"),
    ({"method": "dop853", "tol": 1e-9, "n_out": 10**9}, "n_out", "n_out"),
    ({"method": "dop853", "tol": 1e-9, "h": 1e-3}, "adaptive", "step"),
])
def test_unreasonable_options_are_refused_with_the_reason(kwargs, words, param):
    """Relative to the time scale of the motion (here 1, a dimensionless scene); the error carries
    the setting and the value it refused (runtime/errors.py)."""
    args = {"t_end": 10.0, "time_scale": 1.0}
    args.update(kwargs)
    with pytest.raises(UserError, match=words) as err:
        check_options(**args)
    assert "\n" not in str(err.value)
    given = {"tol": args.get("tol"), "step": args.get("h"), "t_end": args["t_end"], "n_out": args.get("n_out")}
    assert (err.value.param, err.value.value) == (param, given[param])
    assert err.value.unit == ("s" if param in ("step", "t_end") else "")


def test_the_budgets_sentences_carry_their_time_unit():
    """A refused step or run length says its times as quantities in s (runtime/words.py), shown in
    s in an SI scene and in time units in a dimensionless one: '--step 1 s is longer than the run
    --t-end 0.5 s' (each setting named as the face spells it), not bare numbers."""
    from levitron.runtime.errors import UserError
    from levitron.runtime.integrate.budget import budget_message, check_options
    from levitron.runtime.ui.human import Units
    from levitron.runtime.words import in_units
    with pytest.raises(UserError) as exc:
        check_options("rk4", 0.5, h=1.0)
    assert "--step 1 s is longer than the run --t-end 0.5 s" in exc.value.words("cli"), exc.value
    assert "step 1 time units is longer than the run t_end 0.5 time units" in \
        exc.value.words("api", Units(si=False)), exc.value
    with pytest.raises(UserError) as exc:
        check_options("rk4", 1.0, h=0.1, time_scale=0.01)
    assert "(0.01 s), which it cannot resolve; pass --step <= 0.0005 s" in exc.value.words("cli"), exc.value
    assert "at t = 0.25 s before t_end" in in_units(budget_message(100, 0.25))
