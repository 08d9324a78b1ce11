"""The one table of integrators (thesis 3.1): every fact about an integrator lives here.

Each entry says its name (the CLI choice), its backend ("c": runtime/csrc/integrators.c; "casadi";
"scipy"), its id in the C enum ``lev_method`` (C methods; the library exports the same numbers
through ``lev_method_id`` and tests/test_budgets.py checks both sides), whether it takes a fixed step
(``h``) or controls its error adaptively (``tol``), whether it uses the generated Jacobian, and
whether the energy is monitored in C after every step. runtime.integrate, runtime.simulate,
runtime.scan, runtime.bench and the CLI read it; nothing else lists integrators.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Integrator:
    name: str
    backend: str                 # "c", "casadi" or "scipy"
    fixed_step: bool             # True: a fixed step h; False: adaptive, tolerance tol
    needs_jacobian: bool = False  # uses the generated Jacobian (simplified Newton)
    monitors_energy: bool = False  # the energy is evaluated after every step (in C)
    c_id: int | None = None      # the value of enum lev_method (C methods only)
    engine: str | None = None    # the casadi plugin or scipy's solve_ivp method name


TABLE: tuple[Integrator, ...] = (
    Integrator("euler", "c", True, monitors_energy=True, c_id=0),          # thesis eq. 3.1.2
    Integrator("rk4", "c", True, monitors_energy=True, c_id=1),            # thesis eqs. 3.1.3-3.1.4
    Integrator("dop853", "c", False, monitors_energy=True, c_id=2),
    Integrator("gauss4", "c", True, needs_jacobian=True, monitors_energy=True, c_id=3),
    Integrator("midpoint", "c", True, needs_jacobian=True, monitors_energy=True, c_id=4),
    Integrator("dop853-fixed", "c", True, monitors_energy=True, c_id=5),
    Integrator("vern9", "c", False, monitors_energy=True, c_id=6),         # Verner 9(8), 2010
    Integrator("cvodes", "casadi", False, engine="cvodes"),
    Integrator("casadi-rk", "casadi", True, engine="rk"),
    Integrator("casadi-collocation", "casadi", True, engine="collocation"),
    Integrator("scipy-dop853", "scipy", False, engine="DOP853"),
    Integrator("scipy-rk45", "scipy", False, engine="RK45"),
    Integrator("scipy-radau", "scipy", False, engine="Radau"),
    Integrator("scipy-bdf", "scipy", False, engine="BDF"),
    Integrator("scipy-lsoda", "scipy", False, engine="LSODA"),
)

BY_NAME: dict[str, Integrator] = {i.name: i for i in TABLE}
METHODS: tuple[str, ...] = tuple(BY_NAME)
DEFAULT = "dop853"          # the integrator of simulate, scan and integrate unless one is named


def lookup(name: str) -> Integrator:
    """The table entry of `name`; an unknown name is a one-line UserError listing the choices."""
    entry = BY_NAME.get(name)
    if entry is None:
        from runtime.errors import UserError
        raise UserError(f"unknown integrator {name!r}; choose one of: {', '.join(METHODS)}")
    return entry


def is_fixed_step(name: str) -> bool:
    return lookup(name).fixed_step
