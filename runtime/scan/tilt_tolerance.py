"""The tilt each spin tolerates: the largest launch tilt that floats a given time, spin by spin.

Linear stability (thesis 3.3.9-3.3.16) says whether the relative equilibrium holds at a spin; it
does not say how far from it a launch may start. Inside the window the top is not equally robust:
where low-order resonances among the linear modes sit (runtime/physics/stability/resonances.py,
docs/resonances.md), a launch with a small tilt can feed the modes and fall although every mode is
linearly stable. This module measures it by simulation, the nonlinear full model (thesis 2.3):

- the spins: N_SPINS log-spaced inside the linear window, INSET of it in from each end;
- at each spin, launches at the hover height tilted by theta (the scene's launch, as `simulate
  --tilt` makes it), the spin held (air friction off: the question is the top at that spin);
- the largest theta in [TILT_LO, TILT_HI] whose launch stays in the box for t_end, by bisection in
  log theta, BISECTIONS steps, every spin's step in one call of the C chunk driver
  (runtime/scan/batch.py simulate_many); a spin that falls even at TILT_LO tolerates 0, one that
  floats at TILT_HI at least TILT_HI.

The bisection assumes that a launch that floats floats at every smaller tilt too; where that fails
it finds one edge of the tolerated tilts. t_end defaults to the maps' run length, PERIODS slow
periods at the window's middle (runtime/scan/stability_map.py); the launch direction is the
scene's default azimuth. A dip is a spin whose tolerance is below DIP of the median's, or below
LOCAL of both its neighbours'; each is named with the nearest resonance (within NEAR of its spin). No sympy here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui import progress
from levitron.runtime.ui.human import Units

N_SPINS = 40
INSET = 0.01           # relative: the spins stay this far inside the window's ends
TILT_LO, TILT_HI = 5e-4, 0.2
BISECTIONS = 10        # log bisection: (TILT_HI / TILT_LO) ** (1 / 2**10): 0.6 % resolution
DIP = 0.5
LOCAL = 0.75
NEAR = 0.03            # relative distance in spin from a dip to the resonance it is named with


@dataclass(frozen=True, repr=False)
class TiltTolerance:
    """The largest launch tilt (rad) that floats t_end (s) at each spin (rad/s, held), with the
    resonances inside the window and the dips; `units`: how the plain view shows numbers."""

    spins: np.ndarray
    max_tilt: np.ndarray
    t_end: float
    resonances: list = field(default_factory=list)
    units: Units = field(default=Units(si=True), compare=False)

    @property
    def dips(self) -> list[dict]:
        """Spins whose tolerance is below DIP of the median's, or a local minimum below LOCAL of
        both neighbours', each with the nearest resonance."""
        median = float(np.median(self.max_tilt))
        tt = self.max_tilt
        out = []
        for i, (w, t) in enumerate(zip(self.spins, tt)):
            local = 0 < i < len(tt) - 1 and t < LOCAL * min(tt[i - 1], tt[i + 1])
            if t < DIP * median or local:
                near = [r for r in self.resonances if abs(r["spin"] - w) <= NEAR * w]
                best = min(near, key=lambda r: abs(r["spin"] - w)) if near else None
                out.append({"spin": float(w), "max_tilt": float(t),
                            "resonance": None if best is None else
                            {k: best[k] for k in ("spin", "order", "relation", "explosive")}})
        return out

    def as_json(self) -> dict:
        return {"spins": self.spins.tolist(), "max_tilt": self.max_tilt.tolist(), "t_end": self.t_end,
                "tilt_range": [TILT_LO, TILT_HI], "dips": self.dips,
                "how": "bisection in log tilt of a launch that stays in its box for t_end, the spin held "
                       "(air friction off), at each spin; runtime/scan/tilt_tolerance.py"}

    def lines(self) -> list[str]:
        """The plain view (`plain_lines` of as_json())."""
        return plain_lines(self.as_json(), self.units)

    def plot(self, path=None, ax=None):
        """The tolerated tilt against the spin, the resonances marked (explosive in red); into `ax`
        (an Axes) or a figure of its own, written to `path` (.png, .pdf, .svg) only when given one.
        Returns the matplotlib Figure (the Axes when given `ax`)."""
        from levitron.runtime.ui.plotting import styled
        with styled():
            return self._draw(path, ax)

    def _draw(self, path, given):
        from levitron.runtime.ui.plotting import canvas, finish
        fig, ax = canvas(given, figsize=(7.5, 4.2))
        ax.plot(self.spins, 1e3 * self.max_tilt, "o-", ms=3, label=f"largest launch tilt floating "
                f"{self.units.time(self.t_end)}")
        for i, r in enumerate(self.resonances):
            ax.axvline(r["spin"], color="C3" if r["explosive"] else "C7", lw=0.9,
                       ls="-" if r["explosive"] else ":",
                       label=("resonance (explosive)" if r["explosive"] else "resonance (bounded)")
                       if i == next(j for j, q in enumerate(self.resonances) if q["explosive"] == r["explosive"])
                       else None)
        ax.set_xlabel(f"spin ({self.units.named('rad/s')})")
        ax.set_ylabel("largest launch tilt (mrad)")
        ax.set_yscale("log")
        ax.legend(fontsize="small")
        if given is None:
            fig.tight_layout()
        return finish(fig, path, "«plot»", ax=given)


def plain_lines(d: dict, u: Units) -> list[str]:
    """The plain view of as_json()'s dict: the range of tolerated tilts, then each dip and the
    resonance beside it."""
    rate = lambda w: u.rate(w).split(" (")[0]     # noqa: E731
    tilts = np.asarray(d["max_tilt"])
    k = int(np.argmin(tilts))
    out = [f"tilt tolerance (the largest launch tilt floating {u.time(d['t_end'])}, the spin held): "
           f"{tilts.max():.3g} rad at best, {tilts[k]:.3g} rad at {rate(d['spins'][k])}"]
    for dip in d["dips"]:
        r = dip["resonance"]
        why = ("" if r is None else f", beside the {r['order']}-wave resonance at {rate(r['spin'])} "
               f"({r['relation']}{', explosive' if r['explosive'] else ''})")
        out.append(f"  dip: {dip['max_tilt']:.3g} rad at {rate(dip['spin'])}{why}")
    return out


def tilt_tolerance(model, window: tuple[float, float], z_s: float, resonances=(), t_end: float | None = None,
                   n: int = N_SPINS) -> TiltTolerance:
    """The curve of the module docstring for the scene's top (its window and hover height z_s)."""
    from levitron.runtime.physics.apparatus.friction import without_friction
    from levitron.runtime.scan.batch import simulate_many
    if window is None:
        raise UserError("the top has no spin interval of linear stability, so no spin to tolerate a tilt")
    p = without_friction(model, model.p)
    lo, hi = window[0] * (1 + INSET), window[1] * (1 - INSET)
    spins = np.geomspace(lo, hi, int(n))
    if t_end is None:
        from levitron.runtime.scan.physics import slow_period
        from levitron.runtime.scan.stability_map import PERIODS
        t_end = PERIODS * slow_period(model, model.param("m"), z_s, math.sqrt(lo * hi))

    def floats(w, tilt) -> np.ndarray:
        r = simulate_many(model, w, tilt=tilt, t_end=t_end, p=p)
        return np.asarray(r["levitating"], bool) & ~np.asarray(r["untested"], bool)
    best = np.zeros(spins.size)
    with progress.task(f"tilt tolerance at {spins.size} spins: bisection steps", total=BISECTIONS + 2,
                       log_every=10.0) as tick:
        low_ok = floats(spins, TILT_LO)
        high_ok = floats(spins, TILT_HI)
        tick(2)
        best[high_ok] = TILT_HI
        open_ = low_ok & ~high_ok
        a = np.full(spins.size, math.log(TILT_LO))
        b = np.full(spins.size, math.log(TILT_HI))
        for _ in range(BISECTIONS):
            idx = np.flatnonzero(open_)
            if idx.size:
                mid = 0.5 * (a[idx] + b[idx])
                ok = floats(spins[idx], np.exp(mid))
                a[idx[ok]] = mid[ok]
                b[idx[~ok]] = mid[~ok]
            tick()
    best[open_] = np.exp(a[open_])
    return TiltTolerance(spins, best, float(t_end), list(resonances), Units.of_scene(model.scene))
