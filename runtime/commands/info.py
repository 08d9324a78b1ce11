"""`levitron info SCENE`: resolved parameters in SI, what is generated, op counts."""
from __future__ import annotations

import math

from derive.scene import MU0

from .common import model_of

NAME = "info"
HELP = "resolved parameters (SI), generated parts and functions, operation counts"


def add_arguments(parser) -> None:
    pass


def run(args) -> dict:
    model = model_of(args)
    scene = model.scene
    params = model.pvals()
    derived = {}
    if "plate_rho" in params:
        rho = params["plate_rho"]
        derived["murho"] = params["mu"] * rho
        derived["dipole_density_A"] = 4 * math.pi * rho / MU0
    m = model.manifest
    return {
        "scene": scene.name,
        "file": str(scene.path),
        "parameters": params,
        "derived_parameters": derived,
        "notes": scene.notes,
        "generated": str(model.folder),
        "input_hash": m.input_hash,
        "plate": m.plate, "coordinates": m.coordinates, "field_order": m.field_order,
        "parts": {k: list(v.states) for k, v in m.parts.items()},
        "functions": {k: {"ops": f.ops, "n_in": f.n_in, "n_out": f.n_out, "doc": f.doc}
                      for k, f in m.functions.items()},
    }
