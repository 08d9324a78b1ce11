"""The words of a Simulations (levitron/results.py, Study.simulate_many's answer): its plain view,
line by line, from its fields, in the scene's display units: what its message, repr and notebook
table say.
"""
from __future__ import annotations

import numpy as np

from levitron.runtime.integrate.verdict import NO_HOVER
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import kept, shown


def summary(sims, u: Units) -> str:
    """"9 runs ended normally; 7 stayed up for the whole 2 s", or which runs did not end normally."""
    n = len(sims)
    bad = np.flatnonzero(~np.isin(sims.status, sims.VERDICTS))
    if bad.size:
        kinds = ", ".join(sorted(set(sims.status[bad].tolist())))
        return f"{bad.size} of {n} runs did not end normally ({kinds}; the first: launch {int(bad[0])})"
    lev = int(np.sum(sims.levitating & ~sims.untested))
    no = np.flatnonzero(sims.status == NO_HOVER)
    ran = n - no.size
    t_end = sims.details.get("t_end")
    text = (f"{ran} runs ended normally; {lev} stayed up for the whole "
            f"{u.time(float('nan') if t_end is None else t_end)}") if ran else "no launch ran"
    if np.any(sims.untested):
        text += f"; {int(np.sum(sims.untested))} launched on the invariant set test nothing"
    if no.size:
        reasons = kept(sims.reason, sims.said.get("reason"), sims.units)
        why = reasons[int(no[0])] if reasons is not None else None
        text += (f"; {no.size} cannot hover (the first, launch {int(no[0])}: "
                 f"{shown(why, u) if why else 'no stable hover height'})")
    return text


def survived(sims, u: Units) -> str:
    """"t_survived: 0.2 s to 2 s of 2 s"."""
    ts, t_end = sims.t_survived, sims.details.get("t_end")
    if not len(sims):
        return ""
    return (f"t_survived: {u.time(float(np.min(ts)))} to {u.time(float(np.max(ts)))} of "
            f"{u.time(float('nan') if t_end is None else t_end)}")


def lines(sims, u: Units) -> list[str]:
    """The plain view: the verdicts, the times survived, how the runs were made."""
    n = len(sims)
    tested = n - int(np.sum(sims.untested))
    d = sims.details
    how = ", ".join(f"{k} {d[k]}" for k in ("integrator", "tol", "lanes") if d.get(k) is not None)
    return [line for line in (
        f"launches: {n}, levitating {int(np.sum(sims.levitating & ~sims.untested))} of {tested} tested",
        summary(sims, u), survived(sims, u), f"runs: {how}" if how else "", u.note) if line]
