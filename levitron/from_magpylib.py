"""Magnets from magpylib: `lev.plate_from_magpylib(collection)` -> a compound [plate] table.

magpylib (>= 5: SI, positions in m, magnetization in A/m, currents in A) is the library in which
people design magnet assemblies; this turns an assembly of sources the plate kinds can express
into a scene's [plate] table, one part per source (scene/plates/compound.py):

    Cuboid, centred on the z axis, sides along x and y        -> rectangle (block)
    Cylinder, on the axis                                     -> ring_magnet (solid)
    CylinderSegment, on the axis, a full turn (360 deg)        -> ring_magnet (r_in = its inner radius)
    Circle, on the axis, in a horizontal plane                -> loop

each magnetised along z (any sign; magnetization, not polarization, is carried over: B = mu0 (H + M)
with the scene's mu0, which is CODATA 2018 and magpylib's CODATA 2022, 6.8e-10 relative apart).
The plates' convention is a top face in z = 0 (docs/contract.md): every magnet's top face and
every loop must lie in one plane, the assembly's top, which becomes z = 0. Anything else is refused
with one line naming the source: a rotated or off-axis source, a magnetisation with an x or y
part, a partial ring, a path of several positions, sources at different heights, and other source
types (spheres, meshes, dipoles, polylines, ...), a number that is not finite (a position, a
magnetisation, a dimension, a current) or a source without its dimension, and a collection of more
than MAX_SOURCES sources (each is a part the model derives and evaluates). magpylib is not a dependency of levitron: the
caller has it, since it passes its objects.
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.errors import UserError
from levitron.scene.plates import KINDS
from levitron.scene.plates.compound import MAX_PARTS

# the parts of one compound plate, the derivation budget of scene/plates/compound.py: each source is a
# part derived and evaluated on its own
MAX_SOURCES = MAX_PARTS
# each kind's scene keys that are lengths (the registry's, unit m): the assembly's size, for the
# tolerance of its one top plane
_LENGTH_KEYS = {name: {k.name for k in kind.keys if k.unit == "m"} for name, kind in KINDS.items()}


def _finite(values, who: str, what: str, size: int | None = None) -> np.ndarray:
    """`values` as finite floats (one-line UserError naming the source and `what` otherwise): a NaN
    compares false with everything, so it would pass every check below as 0 (on the axis, along z)."""
    if values is None:
        raise UserError(f"{who} has no {what}: set it (magpylib leaves it unset until given)")
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise UserError(f"{who} has {what} {values!r}, not numbers: give numbers") from None
    if size is not None and arr.shape[-1:] != (size,):
        raise UserError(f"{who} has {what} {arr.tolist()}: give {size} numbers")
    if not np.all(np.isfinite(arr)):
        raise UserError(f"{who} has {what} {arr.tolist()}, not finite: give finite numbers")
    return arr


def _name(src, i: int) -> str:
    label = getattr(getattr(src, "style", None), "label", None)
    return f"source {i} ({type(src).__name__}{f' {label!r}' if label else ''})"


def _placed(src, who: str, turn_ok: bool) -> tuple[float, np.ndarray]:
    """(z of the source's centre, its local z axis in global coordinates), after the checks that it
    sits on the axis with one position and, unless turn_ok (an axisymmetric source), unrotated."""
    pos = _finite(src.position, who, "position", 3)
    if pos.ndim != 1:
        raise UserError(f"{who} has a path of {len(pos)} positions: give it one position")
    if abs(pos[0]) > 0 or abs(pos[1]) > 0:
        raise UserError(f"{who} sits at x, y = {pos[0]:.6g}, {pos[1]:.6g} m, off the z axis: the plate "
                        "kinds are centred on the axis; move it to x = y = 0")
    rot = src.orientation.as_matrix()
    rot = rot[0] if rot.ndim == 3 else rot
    axis = rot[:, 2]
    if not np.allclose(axis, [0.0, 0.0, 1.0], atol=1e-12):
        raise UserError(f"{who} is tilted (its axis points along {np.round(axis, 6).tolist()}): the "
                        "plate kinds are magnetised along z; give it no rotation")
    if not turn_ok and not np.allclose(rot, np.eye(3), atol=1e-12):
        raise UserError(f"{who} is turned about z: a rectangle's sides lie along x and y; give it no "
                        "rotation (swap its dimensions for a quarter turn)")
    return float(pos[2]), axis


def _magnetization(src, who: str) -> float:
    m = _finite(src.magnetization, who, "magnetization", 3)
    if m.ndim != 1:
        raise UserError(f"{who} has a magnetisation that changes along a path: give it one")
    if abs(m[0]) > 0 or abs(m[1]) > 0 or not m[2]:
        raise UserError(f"{who} has magnetization {m.tolist()} A/m: the plate kinds are magnetised "
                        "along z only (give (0, 0, M), M != 0)")
    return float(m[2])


def _part(src, i: int, magpy) -> tuple[dict, float]:
    """(the part's table, the height of its top face or plane)."""
    who = _name(src, i)
    if isinstance(src, magpy.magnet.Cuboid):
        zc, _ = _placed(src, who, turn_ok=False)
        a, b, c = (float(v) for v in _finite(src.dimension, who, "dimension", 3))
        return ({"kind": "rectangle", "side_x": a, "side_y": b, "thickness": c,
                 "magnetization": _magnetization(src, who)}, zc + c / 2)
    if isinstance(src, magpy.magnet.Cylinder):
        zc, _ = _placed(src, who, turn_ok=True)
        d, h = (float(v) for v in _finite(src.dimension, who, "dimension", 2))
        return ({"kind": "ring_magnet", "r_out": d / 2, "thickness": h,
                 "magnetization": _magnetization(src, who)}, zc + h / 2)
    if isinstance(src, magpy.magnet.CylinderSegment):
        zc, _ = _placed(src, who, turn_ok=True)
        r1, r2, h, phi1, phi2 = (float(v) for v in _finite(src.dimension, who, "dimension", 5))
        if not math.isclose(phi2 - phi1, 360.0, rel_tol=0, abs_tol=1e-9):
            raise UserError(f"{who} spans {phi2 - phi1:g} deg, not a full turn: the plate kinds are "
                            "axisymmetric rings (give phi2 - phi1 = 360)")
        part = {"kind": "ring_magnet", "r_out": r2, "thickness": h, "magnetization": _magnetization(src, who)}
        if r1 > 0:
            part["r_in"] = r1
        return part, zc + h / 2
    if isinstance(src, magpy.current.Circle):
        zc, _ = _placed(src, who, turn_ok=True)
        current = float(_finite(src.current, who, "current").reshape(-1)[0])
        diameter = float(_finite(src.diameter, who, "diameter").reshape(-1)[0])
        return {"kind": "loop", "radius": diameter / 2, "current": current}, zc
    raise UserError(f"{who} is not supported: the plate kinds express Cuboid, Cylinder, CylinderSegment "
                    "(a full turn) and Circle sources on the z axis, magnetised along z")


def plate_from_magpylib(collection) -> dict:
    """The [plate] table (kind "compound", one part per source, in the collection's order) of a
    magpylib source or Collection, the assembly's top plane moved to z = 0 (module docstring).
    Raises levitron.UserError (one line naming the source) for what the plate kinds cannot express."""
    import magpylib as magpy
    if int(magpy.__version__.split(".")[0]) < 5:
        raise UserError(f"magpylib {magpy.__version__} works in mm and mT: install magpylib >= 5 (SI)")
    sources = list(collection.sources_all) if isinstance(collection, magpy.Collection) else [collection]
    if not sources:
        raise UserError("the collection has no sources: add magnets or loops to it")
    if len(sources) > MAX_SOURCES:
        raise UserError(f"the collection has {len(sources)} sources, more than the {MAX_SOURCES} one "
                        "plate takes (the derivation budget: each source is a part derived on its own): "
                        "merge rings of one radius, or model fewer magnets")
    parts, tops = [], []
    for i, src in enumerate(sources):
        part, top = _part(src, i, magpy)
        parts.append(part)
        tops.append(top)
    size = max(max(v for k, v in p.items() if k in _LENGTH_KEYS[p["kind"]]) for p in parts)
    highest = max(tops)
    for i, top in enumerate(tops):
        if abs(top - highest) > 1e-12 * size:
            raise UserError(f"{_name(sources[i], i)} has its top at z = {top:.6g} m, the assembly's top "
                            f"is at {highest:.6g} m: the plate kinds have one top plane, z = 0; put "
                            "every magnet's top face (and every loop) in one plane")
    return {"kind": "compound", "parts": parts}
