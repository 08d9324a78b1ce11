"""The plate registry, derive side: one sympy builder per kind (derive/plate_fields/<kind>.py,
`build(table, prefix) -> Plate`), for the same kinds as the scene side (scene/plates/)."""
from __future__ import annotations

import importlib
from collections.abc import Callable

from levitron.scene.plates import KINDS

from .plate import Plate, plate_symbol

__all__ = ["BUILDERS", "Plate", "build_plate", "plate_symbol"]

BUILDERS: dict[str, Callable[..., Plate]] = {
    kind: importlib.import_module(f"{__name__}.{kind}").build for kind in KINDS}


def build_plate(table: dict, prefix: str = "") -> Plate:
    """The Plate of a validated [plate] table (or of part `prefix` = "p<i>_" of a compound one)."""
    kind = table["kind"]
    if KINDS[kind].has_parts:
        return BUILDERS[kind](table, prefix, build_part=build_plate)
    return BUILDERS[kind](table, prefix)
