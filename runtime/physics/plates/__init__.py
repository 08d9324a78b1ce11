"""The plate registry, runtime side: the exact field of each plate kind (numpy, no sympy).

One module per kind (runtime/physics/plates/<kind>.py, the same kinds as scene/plates/) defines
`field(table, p, points, part_field) -> B (N, 3) | None` (None: no closed form), with the closed
forms of runtime/physics/field/exact_field.py. `p` reads the kind's resolved parameters (Scene.params
`plate_<name>`, compound part i `plate_p<i>_<name>`); `part_field` is `plate_field`, for compound
plates.
"""
from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping

import numpy as np

from levitron.scene.plates import KINDS


class Params:
    """A plate's (or a part's) resolved parameters: p["a"] is params["plate_a"] (with the part's
    prefix: params["plate_p<i>_a"])."""

    def __init__(self, params: Mapping[str, float], prefix: str = "plate_"):
        self.params = params
        self.prefix = prefix

    def __getitem__(self, name: str) -> float:
        return float(self.params[self.prefix + name])

    def part(self, i: int) -> Params:
        return Params(self.params, f"{self.prefix}p{i}_")


FIELDS: dict[str, Callable] = {
    kind: importlib.import_module(f"{__name__}.{kind}").field for kind in KINDS}


def plate_field(table: Mapping, params, points) -> np.ndarray | None:
    """The exact B (N, 3) of a scene's plate at points (N, 3), or None when its kind has no closed
    form (expression plates). `table` is Scene.data["plate"] (or a part of it), `params`
    Scene.params or a Params. Thin plates given by `murho` without a top moment use the nominal
    moment of Scene.notes, as the model does."""
    p = params if isinstance(params, Params) else Params(params)
    return FIELDS[table["kind"]](table, p, np.asarray(points, dtype=float), plate_field)
