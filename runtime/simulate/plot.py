"""Pictures of one run: height, radial offset and tilt against time, or for a flight in air the
spin and the height with the linear limits and the adiabatic crossing (matplotlib without pyplot;
runtime/ui/plotting.py style; the scene's units, runtime/ui/human.py). Each draws its panels on a
figure of its own, on `fig` (a Figure or SubFigure) or into `ax` (a list of as many Axes), writes
`path` when given one, and returns the Figure (the list of Axes when given `ax`)."""
from __future__ import annotations

import numpy as np

from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plotting import canvas, finish, in_style


@in_style
def draw(t, dz, r, tilt, path, info, u: Units, scene: str = "", ax=None, fig=None):
    """Height above z_s, radial offset and tilt against time (three panels; runtime/ui/plotting.py
    style): mm and s in an SI scene, the scene's own units otherwise (u: runtime/ui/human.py)."""
    given, made = ax, ax is None and fig is None
    k, lu, tu = (1e3, "mm", "s") if u.si else (1.0, "scene units", "time units")
    fig, ax = canvas(given, fig, nrows=3, sharex=True, figsize=(7, 7))
    ax[0].plot(t, dz * k, label="z - z_s")
    ax[0].axhline(0, color="0.5", lw=0.8, ls="--", label=f"z_s = {u.length(info['z_s'])}")
    ax[0].set_ylabel(f"height above z_s ({lu})")
    ax[1].plot(t, r * k, color="C1", label="sqrt(x^2 + y^2)")
    ax[1].set_ylabel(f"radial offset ({lu})")
    ax[2].plot(t, np.degrees(tilt), color="C2", label="angle of the axis to the vertical")
    ax[2].set_ylabel("tilt (deg)")
    ax[2].set_xlabel(f"t ({tu})")
    for a in ax:
        a.legend(loc="best")
    verdict = "levitating" if info["levitating"] else info["status"]
    ax[0].set_title(f"{scene}: spin {u.rate(info['spin']['rad_s'], 4)}, z_s = {u.length(info['z_s'])}\n"
                    f"{verdict} for {u.time(info['t_survived'])}", fontsize="medium")
    if made:
        fig.tight_layout()
    return finish(fig, path, ax=given)


@in_style
def draw_flight(t, dz, w, path, info, u: Units, scene: str = "", ax=None, fig=None):
    """A flight in air: the spin and the height above z_s against time (two panels), with the linear
    spin limits at z_s and the adiabatic crossing time drawn in (runtime/physics/apparatus/friction.py; u:
    runtime/ui/human.py)."""
    given, made = ax, ax is None and fig is None
    fl = info["flight"]
    k, lu, tu, ru = (1e3, "mm", "s", "rad/s") if u.si else (1.0, "scene units", "time units", "rad/time")
    fig, ax = canvas(given, fig, nrows=2, sharex=True, figsize=(7, 6))
    ax[0].plot(t, w, label="spin omega_3")
    iv = fl["spin_interval"]
    if iv:
        ax[0].axhline(iv[0], color="C3", ls="--", lw=1, label=f"lower limit {sig(iv[0], 4)} {ru}")
        if iv[1] < 1.2 * max(w):
            ax[0].axhline(iv[1], color="C4", ls="--", lw=1, label=f"upper limit {sig(iv[1], 4)} {ru}")
    shown = fl["t_cross"] is not None and t[0] <= fl["t_cross"] <= t[-1]   # axes fitted to the run
    if shown:
        for a in ax:
            a.axvline(fl["t_cross"], color="0.5", ls=":", lw=1)
        ax[0].plot([], [], color="0.5", ls=":", label=f"adiabatic crossing t = {sig(fl['t_cross'], 4)} {tu}")
    ax[0].set_ylabel(f"spin ({ru})")
    ax[1].plot(t, dz * k, color="C1", label="z - z_s")
    ax[1].set_ylabel(f"height above z_s ({lu})")
    ax[1].set_xlabel(f"t ({tu})")
    ax[1].set_xlim(t[0], t[-1])
    if fl["t_cross"] is not None and not shown:
        ax[0].plot([], [], " ", label=f"adiabatic crossing at t = {sig(fl['t_cross'], 4)} {tu}, after this run")
    for a in ax:
        a.legend(loc="best", fontsize="small")
    verdict = (f"falls after {sig(fl['flight_time'], 4)} {tu} at spin {sig(fl['fall_spin'], 4)} {ru}"
               if fl["fell"] else f"still up after {sig(info['t_survived'], 4)} {tu}")
    # two lines, as draw_trajectory's: one ran past the figure's right edge with "time units"
    ax[0].set_title(f"{scene} in air: launched at {sig(info['spin']['rad_s'], 4)} {ru}\n{verdict}",
                    fontsize="medium")
    if made:
        fig.tight_layout()
    return finish(fig, path, ax=given)
