"""What a run's status says of the top, the one definition the commands and the maps share.

A run gives a verdict when it reaches t_end (the top stayed up: "completed") or stops where the top
leaves its box ("left_box": it fell). A run that ends before t_end for any other reason (its step
budget, a non-finite state, a step underflow, runtime/integrate/c_backend.py STATUS) says nothing
of the top: no verdict, neither up nor down. A map's point with no equilibrium at its mass is not
run at all (NO_HOVER); "" is a map's point without a status.

Nor does a run that reached t_end give a verdict where the physics cannot support one
(`past_window`): its spin has left the stable window, below the lower critical spin, so that the
adiabatic prediction puts the fall before the run's end, and the run ended before the fall showed
(a top falls some time after its spin crosses the limit): the one test for every run in air
(runtime/simulate/run.py; a launch's or a map's point passes its spin by the decay law). A map's
point judged so keeps the status PAST_WINDOW: it reached t_end, so it did not stop early, and it is
no verdict all the same.
"""
from __future__ import annotations

from levitron.runtime.words import si

UP, DOWN = "completed", "left_box"
NO_HOVER = "no_hover_height"       # a map's point with no equilibrium: nothing simulated
NOT_RUN = (NO_HOVER, "")
PAST_WINDOW = "past_window"        # a map's point up at t_end, its spin below the window: no verdict


def verdict(status: str) -> bool | None:
    """True (stayed up), False (fell) or None (the run stopped early: no verdict)."""
    return True if status == UP else False if status == DOWN else None


def stopped_early(status: str) -> bool:
    """A run that ended before t_end without the top leaving its box (verdict None), not a map's
    point that was never run."""
    return status not in (UP, DOWN, PAST_WINDOW) and status not in NOT_RUN


def no_verdict(status: str) -> bool:
    """A point that was run and says nothing of the top: it stopped early, or it is PAST_WINDOW."""
    return status == PAST_WINDOW or stopped_early(status)


def no_verdict_reason(status: str, message: str) -> str:
    """Why a run that stopped early gives no verdict (simulate's `untested`)."""
    return (f"the run stopped early ({status}) before t_end, so it says nothing of whether the top "
            f"stays up: {message}")


def past_window(status: str, t_end: float, lower: float | None, spin_end: float | None,
                t_cross: float | None = None) -> str | None:
    """Why a run that reached t_end ("completed") gives no verdict all the same (module docstring),
    or None where its verdict stands: `lower` the lower critical spin of the top (None: no window
    known), `spin_end` the spin at the run's end, `t_cross` the adiabatic prediction of the fall,
    tau ln(omega_0 / sigma_lo) (runtime/physics/apparatus/friction.py crossing_time; 0: launched below it)."""
    if status != UP or lower is None or spin_end is None or not abs(spin_end) < lower:
        return None
    when = ("it started below it" if not t_cross else
            f"the adiabatic prediction puts the fall at {si(t_cross, 's')}, before the run's end {si(t_end, 's')}")
    return (f"the spin at the run's end, {si(abs(spin_end), 'rad/s')}, is below the lower critical spin "
            f"{si(lower, 'rad/s')} ({when}): the top is past its stable window and the run ended before "
            "its fall showed, so it says nothing of whether the top stays up; run longer («t_end»)")
