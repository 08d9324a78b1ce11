"""The set-up as drawn to scale: the base's outline (from the scene's plate keys), the top as a disc
of its own mass and axial moment, the hover height, the stable band and z_c (no plotting here).

    shape = setup_of(model, p)         # a JSON-able dict, in the scene's lengths (SI: m)

The base: each plate kind declares its outline beside its keys (scene/plates/<kind>.py `outline`,
scene/plates/base.py): an annulus or disk plate is a thin layer in z = 0 (thesis 2.2.11); a ring
magnet or a block fills -thickness <= z <= 0 (a rectangle's hole is its r_in); a loop is a wire of
its radius in z = 0; a compound plate is its parts; an expression plate has no outline (None).
The top: a uniform cylinder of the top's mass m with its axial moment C = m r^2 / 2, so
r = sqrt(2 C / m), and its transverse A = m (3 r^2 + h^2) / 12 for the height h (0 where that
gives none): the scene gives no size of the top, only these.
"""
from __future__ import annotations

import math

from levitron.scene.plates import KINDS


def _part(table: dict) -> dict | None:
    """One plate table's outline, as its kind declares it (scene/plates/<kind>.py `outline`):
    {"kind": "disc"|"ring"|"rect"|"loop", "r_out", "r_in", "half_x", "half_y", "thickness"} (lengths
    as the scene writes them), or None (a kind without an outline)."""
    kind = _kind(table)
    return kind.outline(table) if kind is not None and kind.outline is not None else None


def _kind(table: dict):
    """The registry's PlateKind of a plate table (None for a kind it does not know)."""
    name = table.get("kind")
    return KINDS.get(name) if isinstance(name, str) else None


def base_of(plate: dict) -> list[dict]:
    """The base's outlines (a compound plate: one per part, its compound parts' parts included; a
    kind without an outline, an expression plate: none)."""
    kind = _kind(plate)
    if kind is not None and kind.has_parts:
        return [s for p in plate.get("parts", []) for s in base_of(p)]
    one = _part(plate)
    return [one] if one is not None else []


def extent(base: list[dict]) -> float:
    """The base's largest horizontal half-width (0 without an outline)."""
    return max([max(s.get("r_out", 0.0), s.get("half_x", 0.0), s.get("half_y", 0.0)) for s in base],
               default=0.0)


def top_disc(m: float, A: float, C: float) -> tuple[float, float]:
    """(radius, height) of the uniform cylinder of mass m and moments A, C (module docstring)."""
    r = math.sqrt(2 * C / m)
    h2 = 12 * A / m - 3 * r * r
    return r, math.sqrt(h2) if h2 > 0 else 0.0


def setup_of(model, p=None, bands: bool = False) -> dict:
    """The drawing's numbers: base outlines, the top's disc, z_s (None where it cannot hover) and,
    with bands, the stable band and the critical height z_c (thesis 3.3.3)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    pv = model.pvals(p)
    r, h = top_disc(pv["m"], pv["A"], pv["C"])
    out = {"base": base_of(model.scene.data["plate"]), "top_radius": r, "top_height": h, "C": pv["C"],
           "scale": eqm.scale_of(model, p), "z_s": None, "band": None, "z_c": None}
    rep = eqm.equilibria_of(model, p, bands=bands)
    out["z_s"] = rep.stable[0].z if rep.stable else None
    if bands:
        band = rep.stable_band
        out["band"] = list(band.z) if band is not None else None
        on = eqm.model_onaxis(model, model.p if p is None else p)
        out["z_c"] = eqm.critical_height(on, pv["g"], pv["mu"], out["scale"])[0]
    return out
