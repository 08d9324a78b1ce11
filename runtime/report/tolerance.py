"""The report's spin-window figure with the tilt each spin tolerates: the small stability map over
spin and tilt above, below it on the same spins the largest launch tilt that floats
(runtime/scan/tilt_tolerance.py), with the resonances inside the window marked (vertical lines,
labelled with their order; explosive ones red).

The curve needs simulations: a bisection at each of SPINS spins (a coarse grid; `stability
«tilt_tolerance»` runs 40) over the map's run length. It is computed once into the cache,
`$LEVITRON_CACHE/figures/tilt_tolerance-<hash of its inputs>.json` (as figures 3.2-3.3 are,
runtime/cli/commands/figures.py): the derived model (its folder's content hash), the parameters,
the window, the hover height, the run length, the grid, the code that computes it (this module,
tilt_tolerance.py, the batch and the C chunk driver, runtime/csrc) and the package's version. A
damaged entry is computed again. No sympy here.
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

SPINS = 12            # the report's grid: coarse (the command's curve has 40)
LABELLED = 6          # resonances labelled on the figure, the strongest first (all drawn)


def _key(model, window, z_s: float, t_end: float, n: int) -> str:
    from levitron.runtime.scan import batch, chunk_c, tilt_tolerance
    from levitron.runtime.ui.provenance import version
    h = hashlib.sha256(json.dumps({"version": version(), "model": Path(model.folder).name,
                                   "names": list(model.param_names), "p": [float(v) for v in model.p],
                                   "window": [float(w) for w in window], "z_s": float(z_s),
                                   "t_end": float(t_end), "n": int(n)}, sort_keys=True).encode())
    csrc = Path(batch.__file__).resolve().parents[1] / "csrc"
    sources = sorted(p for p in csrc.iterdir() if p.suffix in (".c", ".h"))
    for path in (Path(__file__), Path(tilt_tolerance.__file__), Path(batch.__file__), Path(chunk_c.__file__),
                 *sources):
        h.update(f"\0{path.name}\0".encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def entry(model, window, z_s: float, t_end: float, n: int = SPINS) -> Path:
    """The cache file of the curve with these inputs (runtime/model/cbuild.py cache_dir)."""
    from levitron.runtime.model.cbuild import cache_dir
    return cache_dir() / "figures" / f"tilt_tolerance-{_key(model, window, z_s, t_end, n)[:32]}.json"


def curve(model, window, z_s: float, resonances, t_end: float | None = None, n: int = SPINS):
    """(the TiltTolerance at n spins inside the window, whether it came from the cache); t_end
    None: the command's, PERIODS slow periods at the middle of the spins (tilt_tolerance.py)."""
    import math

    from levitron.runtime.scan.physics import slow_period
    from levitron.runtime.scan.stability_map import PERIODS
    from levitron.runtime.scan.tilt_tolerance import INSET, TiltTolerance, tilt_tolerance
    from levitron.runtime.ui.atomic import write_text
    from levitron.runtime.ui.human import Units
    if t_end is None:
        mid = math.sqrt(window[0] * (1 + INSET) * window[1] * (1 - INSET))
        t_end = PERIODS * slow_period(model, model.param("m"), z_s, mid)
    path = entry(model, window, z_s, t_end, n)
    try:
        d = json.loads(path.read_text())
        spins, tilts = np.asarray(d["spins"], float), np.asarray(d["max_tilt"], float)
        if spins.shape == tilts.shape == (n,) and np.all(np.isfinite(tilts)):
            return TiltTolerance(spins, tilts, float(d["t_end"]), list(resonances), Units.of_scene(model.scene)), True
    except (OSError, ValueError, TypeError, KeyError):
        pass
    c = tilt_tolerance(model, window, z_s, resonances, t_end=t_end, n=n)
    write_text(path, json.dumps({"spins": c.spins.tolist(), "max_tilt": c.max_tilt.tolist(), "t_end": c.t_end}),
               "LEVITRON_CACHE")
    return c, False


def figure(scan, tol, path, units) -> Path:
    """The map (runtime/scan/plot.py) above the tolerance curve, sharing the spins, the resonances
    marked on both and labelled on the curve's panel; written to `path` (.png)."""
    from levitron.runtime.ui.plotting import canvas, save_figure, styled
    with styled():
        fig, (top, low) = canvas(nrows=2, figsize=(8, 9), gridspec_kw={"height_ratios": [5, 3.4]})
        scan.plot(ax=top)
        tol.plot(ax=low)
        low.set_xlim(top.get_xlim())
        rate = units.named("rad/s")
        for i, r in enumerate(tol.resonances):
            colour = "C3" if r["explosive"] else "C7"
            top.axvline(r["spin"], color=colour, lw=0.7, ls="--" if r["explosive"] else ":")
            if i < LABELLED:
                low.annotate(f"{r['order']}-wave {units.rate(r['spin']).split(' (')[0]}",
                             (r["spin"], 1.0), xycoords=("data", "axes fraction"), xytext=(2, -4),
                             textcoords="offset points", rotation=90, va="top", ha="left", fontsize=7,
                             color=colour)
        low.set_title(f"the largest launch tilt that floats, at {tol.spins.size} spins inside the window "
                      f"(spin held; {rate}); resonances: red explosive, grey bounded", fontsize=8)
        fig.tight_layout()
        return save_figure(fig, path)
