"""`levitron equilibrium SCENE`: vertical equilibria, z_c, the largest mass, the stable band.

Thesis 3.3.1-3.3.3 and the stable band of DESIGN.md (runtime/equilibrium.py); beside it the
adiabatic (Berry-Simon) band, never instead.
"""
from __future__ import annotations

import time

from .. import equilibrium as eqm
from .. import linear
from .common import model_of

NAME = "equilibrium"
HELP = "vertical equilibria, z_c, the largest mass, and the band where a spin can stabilise the top"


def add_arguments(parser) -> None:
    parser.add_argument("--plot", metavar="FILE", default=None,
                        help="also draw the equilibrium condition (thesis fig. 3.5) into FILE (.png)")


def _band(b):
    return None if b is None else b.as_dict()


def run(args) -> dict:
    model = model_of(args)
    P = {n: float(v) for n, v in zip(model.manifest["parameters"], model.p)}
    m, g, A, C, mu = P["m"], P["g"], P["A"], P["C"], P["mu"]
    scale = eqm.length_scale(P)
    onaxis = linear.model_onaxis(model)
    t0 = time.perf_counter()
    rep = eqm.analyse(onaxis, m, g, A, C, mu, scale)
    wall = time.perf_counter() - t0
    band = rep.stable_band
    reasons = []
    if not rep.equilibria:
        if rep.max_mass is not None and rep.max_mass < m:
            reasons.append(f"the top (m = {m:.6g} kg) is too heavy: the plate holds at most "
                           f"{rep.max_mass:.6g} kg (at z_c = {rep.z_c:.6g} m)")
        else:
            reasons.append("m g + mu Phi_2(z) has no root for z > 0: the field cannot hold this top")
    elif not any(e.vertically_stable for e in rep.equilibria):
        reasons.append("no equilibrium is vertically stable (mu Phi_3 <= 0 at every root, thesis 3.3.3)")
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
        "equilibria": [{"z": e.z, "vertically_stable": e.vertically_stable,
                        "stiffness": e.stiffness} for e in rep.equilibria],
        "z_c": rep.z_c,
        "max_mass": rep.max_mass,
        "stable_band": _band(band),
        "stable_bands": [b.as_dict() for b in rep.stable_bands],
        "adiabatic_band": _band(rep.adiabatic_band),
        "adiabatic_note": "Berry-Simon: |B| has a minimum on the axis (sign(Phi_1) Phi_3 > 0 and "
                          "Phi_2^2 > 2 Phi_1 Phi_3); an approximation for fast spin, reported beside "
                          "the exact band, never instead",
        "reason": "; ".join(reasons) if reasons else None,
        "length_scale": scale,
        "wall_s": wall,
    }
    if args.plot:
        from ..figures_stability import figure_3_5
        from pathlib import Path
        out["plot"] = str(figure_3_5(model, Path(args.plot)))
    return out
