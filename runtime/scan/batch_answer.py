"""Simulations: the answer of runtime/scan/batch.py `simulate_many` (Study.simulate_many), many
launches in one call of the C chunk driver as arrays; its words are runtime/simulate/simulations_view.py,
its table runtime/ui/frames.py. levitron/results.py re-exports it with the other answers."""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.verdict import NO_HOVER
from levitron.runtime.simulate.simulation import NORMAL_ENDS
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import NOTHING_SAID, said
from levitron.runtime.words import render

_SI = Units(si=True)


@dataclass(frozen=True, repr=False)
class Simulations:
    """Many launches in one call of the C chunk driver (Study.simulate_many, runtime/scan/batch.py),
    each the run Study.simulate makes with the same options, as arrays of length n: levitating
    (bool: the run reached t_end), untested (a launch on the invariant set, which tests nothing, or
    a run that stopped early without a verdict: Study.simulate's levitating None), status
    (runtime/integrate/c_backend.py STATUS names),
    t_survived (s), rhs_evals (without simulate's dense-output evaluations), steps, z_s (m, each
    launch's hover height), final_states (n, len(states)), SI; inputs: the launch columns
    {spin (rad/s), tilt (rad), offset (m), azimuth (rad), and any varied scene keys}; wall_s (s,
    the whole call); details: t_end, integrator, tol, lanes (whether the lane variant ran);
    reason: per launch, why its top cannot hover (None where it can): such a launch is not run,
    its status "no_hover_height", levitating False, t_survived 0, z_s and final state NaN."""

    levitating: np.ndarray
    untested: np.ndarray
    status: np.ndarray
    t_survived: np.ndarray
    rhs_evals: np.ndarray
    steps: np.ndarray
    z_s: np.ndarray
    final_states: np.ndarray
    states: list
    inputs: dict
    wall_s: float
    details: dict = field(default_factory=dict)
    units: Units = field(default=_SI, repr=False, compare=False)   # how repr and message show numbers
    reason: np.ndarray | None = None
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, compare=False)   # reason as written (markers)

    def __post_init__(self):
        # the reasons as the runtime wrote them (quantity markers), kept when the API words the
        # fields for its face (dataclasses.replace passes `said` on): its views render them
        if not self.said and self.reason is not None:
            object.__setattr__(self, "said", said(reason=list(self.reason)))

    # a launch's verdict: its run ended normally, or its top cannot hover (not run: no solver's failure)
    VERDICTS = NORMAL_ENDS + (NO_HOVER,)

    def __len__(self) -> int:
        return int(self.status.size)

    def final_state(self, i: int) -> dict:
        """Launch i's final state by name, as Study.simulate's final_state."""
        n = len(self)
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise UserError(f"final_state({i!r}): give a launch index from 0 to {n - 1} (or -1 for the last)")
        return {k: float(v) for k, v in zip(self.states, self.final_states[i])}

    @property
    def success(self) -> bool:
        """Every launch has its verdict: its run ended normally (reached t_end, or stopped when the
        top left the box), or its top cannot hover."""
        return bool(np.all(np.isin(self.status, self.VERDICTS)))

    # ---- its words, one function for every face (runtime/simulate/simulations_view.py)
    def lines(self, units: Units | None = None) -> list[str]:
        """The plain view in `units` (default the scene's): the verdicts, the times survived."""
        from levitron.runtime.simulate import simulations_view
        return simulations_view.lines(self, units or self.units)

    @property
    def message(self) -> str:
        from levitron.runtime.simulate import simulations_view
        return render(simulations_view.summary(self, self.units), "api", self.units)

    def __repr__(self) -> str:
        from levitron.runtime.simulate import simulations_view
        n, u = len(self), self.units
        lev = int(np.sum(self.levitating & ~self.untested))
        no = int(np.sum(self.status == NO_HOVER))
        return render(text_repr("Simulations", [
            f"n={n}, levitating={lev} of {n - int(np.sum(self.untested))} tested"
            + (f", cannot hover={no}" if no else ""), simulations_view.survived(self, u),
            f"lanes={self.details.get('lanes')}, success={self.success}"]), "api", u)

    def _repr_html_(self) -> str:
        return render(html_table("Simulations", self.lines()), "api", self.units)

    # ---- as a table (runtime/ui/frames.py)
    def columns(self) -> tuple[dict[str, np.ndarray], dict[str, str]]:
        """(columns, units) of `to_pandas`, one entry a launch: the inputs (spin rad/s, tilt rad,
        offset m, azimuth rad, a varied scene key in its unit), levitating, untested, status,
        t_survived (s), rhs_evals, steps, z_s (m), reason ("" where the top can hover) and the final
        state as final_<state>; SI (the scene's units in a dimensionless scene)."""
        from levitron.runtime.ui import frames
        si = {"spin": "rad/s", "tilt": "rad", "offset": "m", "azimuth": "rad"}
        n = len(self)
        cols = {k: np.broadcast_to(np.asarray(v), (n,)) for k, v in self.inputs.items()}
        units = {k: si.get(k) or frames.key_unit(k) for k in cols}
        reason = ["" if r is None else str(r) for r in (self.reason if self.reason is not None else [None] * n)]
        cols.update(levitating=self.levitating, untested=self.untested, status=self.status,
                    t_survived=self.t_survived, rhs_evals=self.rhs_evals, steps=self.steps, z_s=self.z_s,
                    reason=np.array(reason, dtype=str))
        units.update(levitating="1", untested="1", status="text", t_survived="s", rhs_evals="1", steps="1",
                     z_s="m", reason="text")
        for j, s in enumerate(self.states):
            cols[f"final_{s}"] = self.final_states[:, j]
            units[f"final_{s}"] = frames.state_unit(s)
        return cols, frames.shown_units(units, self.units)

    def to_pandas(self):
        """The launches as a pandas DataFrame, one row a launch (`columns()`), the units in
        `df.attrs["units"]` (needs pandas)."""
        from levitron.runtime.ui import frames
        cols, units = self.columns()
        return frames.frame(cols, units, "Simulations.to_pandas()")
