"""The one table of integrators (thesis 3.1): every fact about an integrator lives here.

Each entry says its name (the CLI choice), its backend ("c": runtime/csrc/integrators.c; "casadi";
"scipy"), its id in the C enum ``lev_method`` (C methods; the library exports the same numbers
through ``lev_method_id`` and tests/runtime/integrate/test_budgets.py checks both sides), whether it takes a fixed step
(``h``) or controls its error adaptively (``tol``), whether it uses the generated Jacobian, and
whether the energy is monitored in C after every step. runtime.integrate.run, runtime.simulate.run,
runtime.scan.stability_map, runtime.bench.work_precision and the CLI read it; nothing else lists integrators.

Besides the methods of TABLE, the name ``auto`` is accepted wherever an integrator is named: it
stands for the C method the bench measured cheapest at the requested tolerance (``resolve``:
dop853 down to AUTO_VERN9_BELOW_TOL, vern9 below). It is resolved before any run, and the run
records the method actually used (``Result.method``, simulate's ``integrator``) beside the name
asked for (``details["integrator_requested"]``, simulate's ``integrator_requested``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Integrator:
    name: str
    backend: str                 # "c", "casadi" or "scipy"
    fixed_step: bool             # True: a fixed step h; False: adaptive, tolerance tol
    needs_jacobian: bool = False  # uses the generated Jacobian (simplified Newton)
    monitors_energy: bool = False  # the energy is evaluated after every step (in C)
    needs_taylor: bool = False   # runs on the part's generated Taylor coefficients (the reduced model)
    c_id: int | None = None      # the value of enum lev_method (C methods only)
    engine: str | None = None    # the casadi plugin or scipy's solve_ivp method name
    sweep: tuple = ()            # the bench's values, coarse to fine: tol, or h as a fraction of T_fast
    quick_sweep: tuple = ()      # the same for `levitron bench --quick`


# the bench's sweeps (runtime/bench/work_precision.py reads them from the table)
TOLS = (1e-4, 1e-6, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12)
FINE_TOLS = tuple(10.0 ** (-k / 2) for k in range(8, 31))      # 1e-4 .. 1e-15


TABLE: tuple[Integrator, ...] = (
    Integrator("euler", "c", True, monitors_energy=True, c_id=0,           # thesis eq. 3.1.2
               sweep=(1 / 30, 1 / 300, 1 / 3000, 1 / 30000), quick_sweep=(1 / 300,)),
    Integrator("rk4", "c", True, monitors_energy=True, c_id=1,             # thesis eqs. 3.1.3-3.1.4
               sweep=(1 / 3, 1 / 10, 1 / 30, 1 / 100, 1 / 300, 1 / 1000), quick_sweep=(1 / 30, 1 / 300)),
    Integrator("dop853", "c", False, monitors_energy=True, c_id=2, sweep=FINE_TOLS,
               quick_sweep=(1e-6, 1e-10)),
    Integrator("gauss4", "c", True, needs_jacobian=True, monitors_energy=True, c_id=3,
               sweep=(1 / 3, 1 / 10, 1 / 30, 1 / 100, 1 / 300), quick_sweep=(1 / 30,)),
    Integrator("midpoint", "c", True, needs_jacobian=True, monitors_energy=True, c_id=4,
               sweep=(1 / 30, 1 / 300, 1 / 3000)),
    Integrator("dop853-fixed", "c", True, monitors_energy=True, c_id=5),
    Integrator("vern9", "c", False, monitors_energy=True, c_id=6, sweep=FINE_TOLS),  # Verner 9(8), 2010
    # Taylor's method (Jorba & Zou 2005) over derive/emit/taylor.py's coefficients: the reduced model
    Integrator("taylor", "c", False, monitors_energy=True, needs_taylor=True, c_id=7, sweep=FINE_TOLS,
               quick_sweep=(1e-10,)),
    Integrator("cvodes", "casadi", False, engine="cvodes", sweep=TOLS, quick_sweep=(1e-6,)),
    Integrator("casadi-rk", "casadi", True, engine="rk", sweep=(1 / 30, 1 / 100, 1 / 300),
               quick_sweep=(1 / 30,)),
    Integrator("casadi-collocation", "casadi", True, engine="collocation", sweep=(1 / 3, 1 / 10, 1 / 30)),
    Integrator("scipy-dop853", "scipy", False, engine="DOP853", sweep=TOLS, quick_sweep=(1e-6,)),
    Integrator("scipy-rk45", "scipy", False, engine="RK45"),
    Integrator("scipy-radau", "scipy", False, engine="Radau"),
    Integrator("scipy-bdf", "scipy", False, engine="BDF"),
    Integrator("scipy-lsoda", "scipy", False, engine="LSODA"),
)

AUTO = "auto"
DEFAULT_STEP_FRACTION = 1 / 100   # a fixed-step run without a step takes this part of its fastest period


def default_step(fastest_period: float) -> float:
    """The step of a fixed-step run given none: DEFAULT_STEP_FRACTION of the fastest period."""
    return DEFAULT_STEP_FRACTION * fastest_period
# `auto`'s crossover: vern9 for tol < AUTO_VERN9_BELOW_TOL, dop853 for tol >= it. Measured by
# `make bench` on the full model of four scenes (reports/{thesis_stable,ring_magnet,loop,square}/
# bench_full.csv, the work-precision rows; bench_cheapest_full.csv, the cheapest run per error
# bound). At the same tol vern9 is ~6x more accurate (error ~3 tol against dop853's ~20 tol), so the
# two are compared at equal error: for vern9 tolerances above 1e-10 dop853 reaches vern9's error
# with fewer rhs calls and less wall time; at 1e-10 they tie (within 2% of rhs calls); from 3.2e-11
# (error ~1e-10) down vern9 needs fewer rhs calls in all four scenes (1-5% at 3.2e-11, 9-12% at
# 1e-12). bench_cheapest_full.csv says the same in error terms: dop853 cheapest down to error
# bounds of 1e-10 to 1e-11 (1e-11 for thesis_stable), vern9 below.
AUTO_VERN9_BELOW_TOL = 1e-10
# `auto` in the name lookup (its facts are those of both candidates: C, adaptive, energy in C);
# not in TABLE, which lists the methods that run (tests/runtime/integrate/test_budgets.py checks TABLE against C)
AUTO_ENTRY = Integrator(AUTO, "c", False, monitors_energy=True)

BY_NAME: dict[str, Integrator] = {**{i.name: i for i in TABLE}, AUTO: AUTO_ENTRY}
METHODS: tuple[str, ...] = tuple(BY_NAME)
# the methods that run the full model (simulate, scan, launch): all but taylor
FULL_MODEL_METHODS: tuple[str, ...] = tuple(m for m in METHODS if not BY_NAME[m].needs_taylor)
DEFAULT = "dop853"          # the integrator of simulate, scan and integrate unless one is named


def lookup(name: str) -> Integrator:
    """The table entry of `name`; an unknown name is a one-line UserError listing the choices."""
    entry = BY_NAME.get(name)
    if entry is None:
        from levitron.runtime.errors import UserError
        raise UserError(f"unknown integrator {name!r}; choose one of: {', '.join(METHODS)}")
    return entry


@dataclass(frozen=True)
class Choice:
    """An integrator resolved once (`resolve`), what a run carries from there on: `entry` the table
    entry of the method that runs (for ``auto`` the one it picks), `requested` the name asked for,
    `tol` the tolerance it takes (None for a fixed-step method) and `h` its step (None for an
    adaptive method, and for a fixed-step one whose step is still to be chosen: `with_step`)."""
    entry: Integrator
    requested: str
    tol: float | None = None
    h: float | None = None

    @property
    def name(self) -> str:
        return self.entry.name

    @property
    def fixed_step(self) -> bool:
        return self.entry.fixed_step

    def with_step(self, h: float) -> Choice:
        return replace(self, h=h)

    def details(self) -> dict:
        """What the run records of how its method was chosen (choice_details)."""
        return choice_details(self.requested, self.tol)


def refuse_step(name: str, h) -> None:
    """The one-line UserError of a step given to the adaptive method `name` (it takes a tolerance)."""
    if h is not None and not lookup(name).fixed_step:
        from levitron.runtime.errors import UserError
        raise UserError(f"integrator {name} is adaptive: it takes a tolerance («tol»), not a step "
                        "(«step» is for fixed-step integrators)", param="step", value=h, unit="s")


def resolve(name: str, tol: float | None = None, h: float | None = None) -> Choice:
    """The integrator that runs for the requested `name` (a Choice): `name` itself, or for ``auto``
    the C method the bench measured cheapest at tolerance `tol` (AUTO_VERN9_BELOW_TOL). `auto` takes
    a tolerance, never a fixed step, and so does every adaptive method; an unknown name or a bad
    combination is a one-line UserError."""
    entry = lookup(name)
    if name == AUTO:
        from levitron.runtime.errors import UserError
        if h is not None:
            fixed = ", ".join(i.name for i in TABLE if i.fixed_step)
            raise UserError(f"integrator auto picks an adaptive method from the tolerance and takes no "
                            f"fixed step (h={h}); for a fixed step name a fixed-step method ({fixed})",
                            param="step", value=h, unit="s")
        if tol is None or not math.isfinite(tol) or tol <= 0:
            raise UserError(f"integrator auto picks its method from the tolerance, and tol={tol} is not a "
                            "positive finite number; pass e.g. «tol=1e-9»", param="tol", value=tol)
        entry = BY_NAME["vern9" if tol < AUTO_VERN9_BELOW_TOL else "dop853"]
    refuse_step(entry.name, h)
    return Choice(entry, name, None if entry.fixed_step else tol, h if entry.fixed_step else None)


def refuse_on_full_model(name: str, what: str) -> None:
    """A one-line UserError if method `name` cannot run the full model, which `what` (a command)
    integrates: taylor's coefficients are generated for the reduced model only."""
    if lookup(name).needs_taylor:
        from levitron.runtime.errors import UserError
        raise UserError(f"integrator {name} runs the reduced model only (its Taylor coefficients, "
                        f"derive/emit/taylor.py); {what} runs the full model: choose dop853, vern9 "
                        "or auto")


def auto_note(tol: float) -> str:
    """How ``auto`` chose for `tol` (one line, recorded with every run it resolves)."""
    used = resolve(AUTO, tol).name
    side = "below" if used == "vern9" else "at or above"
    return (f"auto: {used} for tol {tol:g} ({side} the crossover {AUTO_VERN9_BELOW_TOL:g}: "
            "vern9 below, dop853 at or above; runtime/integrate/methods.py)")


def choice_details(requested: str, tol: float | None) -> dict:
    """What a run records of how its method was chosen (Result.details): nothing for a named
    method; for ``auto`` the request and auto_note(tol)."""
    return {"integrator_requested": AUTO, "auto": auto_note(tol)} if requested == AUTO else {}
