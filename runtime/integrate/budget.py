"""Bounded work: the step budget of every integrator run, and the limits of reasonable options.

Every run of every integrator in runtime/integrate/methods.py stops after a step budget (status
"step_budget", thesis 3.1's methods are otherwise unbounded: an adaptive step near a coordinate
singularity shrinks without end). The default budget comes from the run length and the fastest
time scale of the motion, ``time_scale`` (the shortest of the spin period, the nutation period
2 pi A / (C |spin|) and the vertical bounce 2 pi sqrt(m / U''), thesis 3.3.3; runtime.simulate.run
computes it from the scene, never as a fixed number of seconds, since scenes may be dimensionless):

    adaptive:  max_steps = min(cap, max(MIN_BUDGET,
                               BUDGET_MULTIPLE * STEPS_PER_PERIOD * t_end / time_scale))
    fixed:     max_steps = the number of steps t_end / h (+1), at most cap

where cap (``step_cap``) is MAX_STEPS_CAP for the C and CasADi integrators and SCIPY_STEPS_CAP for
scipy's, so that no run takes more than about a minute.

Options that no budget or no double-precision time can serve are refused up front, with the reason
(``check_options``): a tolerance outside [TOL_MIN, TOL_MAX], a fixed step below MIN_STEP_FRACTION of
the fastest period or above it, a run longer than the cap covers, a fastest period below the
resolution of the time variable over t_end, more output samples than MAX_N_OUT.
"""
from __future__ import annotations

import math
import sys

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.methods import lookup, refuse_step
from levitron.runtime.ui.validate import run_length, tolerance
from levitron.runtime.words import si

MAX_STEPS_CAP = 10**7      # absolute cap on the steps of one run, whatever the options ...
SCIPY_STEPS_CAP = 10**5    # ... and for scipy, whose steps cost ~0.1-1 ms (a Python call per stage)
STEPS_PER_PERIOD = 20      # steps an adaptive method is expected to need per fastest period
BUDGET_MULTIPLE = 100      # the default budget: this many times that estimate ...
MIN_BUDGET = 10_000        # ... and never fewer steps than this
MAX_N_OUT = 10**6          # output samples of one run
TOL_MAX, TOL_MIN = 1e-2, 1e-15
MIN_STEP_FRACTION = 1e-9   # a fixed step must be at least this fraction of the fastest period
RESOLUTION_ULPS = 1e3      # a step must span at least this many round-off units of t_end


def fixed_steps(t_end: float, h: float) -> int:
    """The number of steps of a fixed-step run (the C code's own rounding, integrators.c)."""
    return max(1, math.ceil(t_end / h * (1 - 1e-12)))


def step_cap(method: str) -> int:
    """The absolute cap on the steps of one run of `method` (module docstring)."""
    return SCIPY_STEPS_CAP if lookup(method).backend == "scipy" else MAX_STEPS_CAP


def default_budget(method: str, t_end: float, h: float | None = None,
                   time_scale: float | None = None) -> int:
    """The step budget of the module docstring (t_end, h and time_scale already checked)."""
    cap = step_cap(method)
    if lookup(method).fixed_step:
        return min(cap, fixed_steps(t_end, h) + 1)
    if time_scale is None:
        return cap
    est = BUDGET_MULTIPLE * STEPS_PER_PERIOD * t_end / time_scale
    return int(min(cap, max(MIN_BUDGET, math.ceil(est))))


def _s(t: float) -> str:
    """A run time in a message: a quantity in s (runtime/words.py), shown in the scene's units."""
    return si(t, "s", ".3g")


def budget_message(max_steps: int, t: float | None = None) -> str:
    """The message of a run stopped by its step budget."""
    at = "" if t is None else f" at t = {si(t, 's', '.6g')}"
    return (f"stopped: the step budget of {max_steps} steps ran out{at} before t_end (the motion "
            "needs ever smaller steps, e.g. near a singularity of the coordinates; try other "
            "coordinates, a looser «tol» or a shorter «t_end»)")


def _positive(x) -> bool:
    return x is not None and math.isfinite(x) and x > 0


def check_tolerance(method: str, tol) -> None:
    """An adaptive method's tolerance, checked before any model is loaded (a fixed-step method
    takes none; None: the default, nothing to check): positive, finite and within [TOL_MIN,
    TOL_MAX], with check_options's refusals."""
    if lookup(method).fixed_step or tol is None:
        return
    tol = tolerance(tol)
    if tol > TOL_MAX:
        raise UserError(f"«tol» {tol:g} is too loose to trust a verdict; pass «tol» <= {TOL_MAX:g}",
                        param="tol", value=tol, hint=f"pass «tol» <= {TOL_MAX:g}")
    if tol < TOL_MIN:
        raise UserError(f"«tol» {tol:g} is below double precision; pass «tol» >= {TOL_MIN:g}",
                        param="tol", value=tol, hint=f"pass «tol» >= {TOL_MIN:g}")


def check_options(method: str, t_end: float, tol: float | None = None, h: float | None = None,
                  n_out: int = 1, time_scale: float | None = None, what: str = "the fastest period",
                  max_steps: int | None = None) -> None:
    """Refuse options no run can honour, with a one-line UserError naming the reason and the
    allowed range; the error carries the setting it is about (`param` t_end, step, tol, n_out or
    max_steps, its value and unit). `what` names time_scale in the messages (e.g. "the spin period
    2 pi / |spin|")."""
    entry = lookup(method)
    cap = step_cap(method)
    run_length(t_end)           # the one check of a run length, whichever face asked (runtime/ui/validate.py)
    if time_scale is not None and not _positive(time_scale):
        raise UserError(f"{what} is {time_scale}: no time scale to bound the run by")
    if isinstance(n_out, bool) or int(n_out) != n_out or not 1 <= n_out <= MAX_N_OUT:
        raise UserError(f"n_out={n_out} output samples: pass a whole number from 1 to {MAX_N_OUT}",
                        param="n_out", value=n_out)
    if max_steps is not None and not (int(max_steps) == max_steps and 1 <= max_steps <= cap):
        raise UserError(f"max_steps={max_steps}: pass a whole number from 1 to {cap}",
                        param="max_steps", value=max_steps)
    if entry.fixed_step:
        if h is None:
            raise UserError(f"integrator {method} takes a fixed step; pass a step h > 0 («step»; "
                            f"«tol» is not used by {method})", param="step", value=None, unit="s")
        if not _positive(h):
            raise UserError(f"«step» {h} must be positive and finite; pass e.g. «step=1e-4»",
                            param="step", value=h, unit="s")
        if h > t_end:
            raise UserError(f"«step» {_s(h)} is longer than the run «t_end» {_s(t_end)}; pass «step» <= "
                            "«t_end»", param="step", value=h, unit="s")
        if time_scale is not None:
            if h > time_scale:
                raise UserError(f"«step» {_s(h)} is longer than {what} ({_s(time_scale)}), which it "
                                f"cannot resolve; pass «step» <= {_s(time_scale / 20)}", param="step", value=h,
                                unit="s")
            if h < MIN_STEP_FRACTION * time_scale:
                raise UserError(f"«step» {_s(h)} is below {MIN_STEP_FRACTION:g} of {what} "
                                f"({_s(time_scale)}); pass «step» >= {_s(MIN_STEP_FRACTION * time_scale)}",
                                param="step", value=h, unit="s")
        n = fixed_steps(t_end, h)
        if n > cap:
            raise UserError(f"«t_end» {_s(t_end)} at «step» {_s(h)} takes {n:.3g} steps, above the budget "
                            f"cap of {cap:.0e} for {method}; pass «t_end» <= {_s(cap * h)} or a "
                            "larger step", param="t_end", value=t_end, unit="s",
                            hint=f"pass «t_end» <= {_s(cap * h)} or a larger step")
        return
    refuse_step(method, h)
    check_tolerance(method, tolerance(tol))
    if time_scale is None:
        return
    resolvable = RESOLUTION_ULPS * sys.float_info.epsilon * t_end * STEPS_PER_PERIOD
    if time_scale < resolvable:
        raise UserError(f"{what} ({_s(time_scale)}) is below what the time variable resolves over "
                        f"«t_end» {_s(t_end)} (at least {_s(resolvable)}); pass a shorter «t_end» or a "
                        "slower spin", param="t_end", value=t_end, unit="s",
                        hint="pass a shorter «t_end» or a slower spin")
    need = STEPS_PER_PERIOD * t_end / time_scale
    if need > cap:
        raise UserError(f"«t_end» {_s(t_end)} spans {t_end / time_scale:.3g} times {what} "
                        f"({_s(time_scale)}): about {need:.3g} steps, above the budget cap of "
                        f"{cap:.0e} for {method}; pass «t_end» <= {_s(cap * time_scale / STEPS_PER_PERIOD)}",
                        param="t_end", value=t_end, unit="s",
                        hint=f"pass «t_end» <= {_s(cap * time_scale / STEPS_PER_PERIOD)}")
