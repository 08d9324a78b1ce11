"""What a run's status says of the top, the one definition the commands and the maps share.

A run gives a verdict when it reaches t_end (the top stayed up: "completed") or stops where the top
leaves its box ("left_box": it fell). A run that ends before t_end for any other reason (its step
budget, a non-finite state, a step underflow, runtime/integrate/c_backend.py STATUS) says nothing
of the top: no verdict, neither up nor down. A map's point with no equilibrium at its mass is not
run at all (NO_HOVER); "" is a map's point without a status.
"""
from __future__ import annotations

UP, DOWN = "completed", "left_box"
NO_HOVER = "no_hover_height"       # a map's point with no equilibrium: nothing simulated
NOT_RUN = (NO_HOVER, "")


def verdict(status: str) -> bool | None:
    """True (stayed up), False (fell) or None (the run stopped early: no verdict)."""
    return True if status == UP else False if status == DOWN else None


def stopped_early(status: str) -> bool:
    """A run that ended before t_end without the top leaving its box (verdict None), not a map's
    point that was never run."""
    return status not in (UP, DOWN) and status not in NOT_RUN


def no_verdict_reason(status: str, message: str) -> str:
    """Why a run that stopped early gives no verdict (simulate's `untested`)."""
    return (f"the run stopped early ({status}) before t_end, so it says nothing of whether the top "
            f"stays up: {message}")
