"""`success` of a command's JSON answer: what the Python API's answer object says by its scipy-style
`success` property (levitron/results.py), read from the answer's JSON keys with the same rule:

    equilibrium  a vertically stable hover height exists (Equilibria.success)
    stability    a spin interval of linear stability exists (Stability.success)
    simulate     the run ended normally: reached t_end or left the box (Simulation.success)
    scan         every point that was run ended normally (Scan.success)
    launch       every sample has its verdict (LaunchOdds.success)
    trim         the advice floats some launches (Trim.success)

An answer that states its own `success` (optimize's design and fit) keeps it; every other command
(info, field, derive, figures, bench, compare, report, scenes, keys) has no API answer that could
fail short of an error: an answer at all is a success (a failure exits 2 or 3 with no JSON).
tests/cli/test_json_success.py checks the rules against the API's objects.
"""
from __future__ import annotations


def _equilibrium(r: dict) -> bool:
    return any(e.get("vertically_stable") for e in r.get("equilibria") or [])


def _stability(r: dict) -> bool:
    return r.get("spin_interval") is not None


def _simulate(r: dict) -> bool:
    from levitron.runtime.simulate.simulation import NORMAL_ENDS
    status = r.get("status", "completed" if r.get("levitating") else "unknown")
    return status in NORMAL_ENDS


def _scan(r: dict) -> bool:
    from levitron.runtime.integrate.verdict import stopped_early
    return not any(stopped_early(st) for row in r.get("status") or [] for st in row)


def _launch(r: dict) -> bool:
    from levitron.runtime.scan.launch_answer import LaunchOdds
    return not any(k not in LaunchOdds.VERDICTS for k in r.get("outcomes") or {})


def _trim(r: dict) -> bool:
    return (r.get("launch_odds") or {}).get("probability", 0) > 0


RULES = {"equilibrium": _equilibrium, "stability": _stability, "simulate": _simulate, "scan": _scan,
         "launch": _launch, "trim": _trim}


def success(command: str, answer: dict) -> bool:
    """The `success` of `command`'s JSON answer (module docstring)."""
    if "success" in answer:
        return bool(answer["success"])
    rule = RULES.get(command)
    return True if rule is None else bool(rule(answer))
