"""`levitron equilibrium SCENE`: vertical equilibria, z_c, the largest mass, the stable band.

Thesis 3.3.1-3.3.3 and the stable band of docs/contract.md (runtime/equilibrium.py); beside it the
adiabatic (Berry-Simon) band, never instead.
"""
from __future__ import annotations

import time

from .. import equilibrium as eqm
from ..plotting import check_plot_path
from .common import model_of

NAME = "equilibrium"
HELP = "vertical equilibria, z_c, the largest mass, and the band where a spin can stabilise the top"


def add_arguments(parser) -> None:
    parser.add_argument("--plot", metavar="FILE", default=None,
                        help="also draw the equilibrium condition (thesis fig. 3.5) into FILE (.png)")


def _band(b):
    return None if b is None else b.as_dict()


def run(args) -> dict:
    if args.plot is not None:
        check_plot_path(args.plot)
    model = model_of(args)
    m = eqm.params_of(model)["m"]
    t0 = time.perf_counter()
    rep = eqm.equilibria_of(model, bands=True)
    wall = time.perf_counter() - t0
    band = rep.stable_band
    reasons = [rep.no_hover_reason(m)] if not rep.stable else []
    if band is None:
        reasons.append("no height admits a spin rate that stabilises the top (no stable band)")
    else:
        zs = [e.z for e in rep.equilibria if e.vertically_stable]
        if zs and not any(band.z[0] <= z <= band.z[1] for z in zs):
            reasons.append(f"this top hovers at z = {zs[0]:.6g} m, outside the stable band "
                           f"[{band.z[0]:.6g}, {band.z[1]:.6g}] m: no spin stabilises it there; a top of "
                           f"mass in [{band.mass[0]:.6g}, {band.mass[1]:.6g}] kg would hover inside it")
    out = {
        "scene": model.scene.name,
        "mass": m,
        "equilibria": [e.as_dict() for e in rep.equilibria],
        "singularities": [s.as_dict() for s in rep.singularities],
        "z_c": rep.z_c,
        "max_mass": rep.max_mass,
        "stable_band": _band(band),
        "stable_bands": [b.as_dict() for b in rep.stable_bands],
        "adiabatic_band": _band(rep.adiabatic_band),
        "adiabatic_note": "Berry-Simon: |B| has a minimum on the axis (sign(Phi_1) Phi_3 > 0 and "
                          "Phi_2^2 > 2 Phi_1 Phi_3); an approximation for fast spin, reported beside "
                          "the exact band, never instead",
        "reason": "; ".join(reasons) if reasons else None,
        "length_scale": eqm.scale_of(model),
        "wall_s": wall,
    }
    if args.plot:
        from pathlib import Path

        from ..figures_stability import figure_3_5
        out["plot"] = str(figure_3_5(model, Path(args.plot)))
    return out
