"""The answers as tables of the ecosystem: pandas DataFrames and xarray Datasets, with their units.

`to_pandas()` of Simulation, Simulations, LaunchOdds and Scan and `to_xarray()` of Scan and
Simulation (the answer modules) build their tables here. pandas and xarray are optional (the
`frames` extra: pip install 'levitron[frames]'); without them the method is a one-line UserError
naming the package to install. The units: a DataFrame carries {column: unit} in
`df.attrs["units"]`; in a Dataset every variable and coordinate carries its own `attrs["units"]`.
The units are those of the numbers (SI in an SI scene; in a dimensionless scene the scene's:
"time units", "rad/time", "scene units"; angles stay rad), as the saved files name them
(runtime/simulate/trajectory_file.py): "1" a pure number (a count, a flag 0/1 or a bool), "text"
a word (a verdict).
"""
from __future__ import annotations

import importlib
from collections.abc import Mapping

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import SI_SYMBOLS

# the trajectory's columns beside the states (runtime/simulate/run.py trajectory_table), SI
DERIVED_UNITS = {"t": "s", "energy": "J", "L_z": "kg m^2/s", "L_n": "kg m^2/s", "tilt": "rad", "spin": "rad/s"}
POSITIONS = ("x", "y", "z")
PLAIN = ("", "1", "rad", "text", "fraction of z_s", "degC")     # the same words in every scene


def need(package: str, what: str):
    """The module `package` ("pandas", "xarray"), or a one-line UserError saying how to install it."""
    try:
        return importlib.import_module(package)
    except ImportError:
        raise UserError(f"{what} needs {package}, which is not installed: pip install {package} "
                        "(or pip install 'levitron[frames]')") from None


def state_unit(name: str) -> str:
    """The SI unit of a model state by its name (manifest.json `parts.*.states`): the position x,
    y, z in m, its momentum p_x, p_y, p_z in kg m/s, every other momentum (an angle's) in kg m^2/s,
    every other state an angle in rad."""
    if name in POSITIONS:
        return "m"
    if name.startswith("p_"):
        return "kg m/s" if name[2:] in POSITIONS else "kg m^2/s"
    return "rad"


def trajectory_unit(name: str) -> str:
    """The SI unit of a column of a run's samples: t, the states, energy, L_z, L_n, tilt, spin."""
    return DERIVED_UNITS.get(name) or state_unit(name)


def shown(si_unit: str, units) -> str:
    """The unit the numbers are in: `si_unit` in an SI scene (runtime/ui/human.py Units); in a
    dimensionless scene the scene's (runtime/ui/human.py Units.named; "scene units" for any other
    dimensional unit), angles, pure numbers and words as they are."""
    if units is None or units.si or si_unit in PLAIN:
        return si_unit
    return units.named(si_unit) if si_unit in SI_SYMBOLS else "scene units"


def shown_units(si_units: Mapping[str, str], units) -> dict[str, str]:
    return {k: shown(u, units) for k, u in si_units.items()}


def key_unit(key: str) -> str:
    """The SI unit of a scene key in `section.key` form ("top.mass" -> "kg", "plate.hole" -> "m"),
    from scene/keys.py and the plate kinds' keys; "" where no table names it."""
    from levitron.scene import keys as k
    from levitron.scene.plates import KINDS
    section, _, name = key.rpartition(".")
    section = section.split(".")[0]
    tables = {"": k.SCENE_KEYS, "top": k.TOP_KEYS, "reference": k.REFERENCE_KEYS, "field": k.FIELD_KEYS,
              "launch": k.LAUNCH_KEYS,
              "plate": (*k.TILT_KEYS, k.TEMPERATURE_KEY, *(key for kind in KINDS.values() for key in kind.keys))}
    return next((entry.unit for entry in tables.get(section, ()) if entry.name == name), "")


def frame(columns: Mapping[str, object], units: Mapping[str, str], what: str, **attrs):
    """A DataFrame of the 1-D columns, `df.attrs["units"]` {column: unit} and the other attrs."""
    pd = need("pandas", what)
    df = pd.DataFrame({n: np.asarray(v) for n, v in columns.items()})
    df.attrs.update(attrs)
    df.attrs["units"] = {n: units.get(n, "") for n in df.columns}
    return df


def dataset(coords: Mapping[str, tuple[object, str]], data: Mapping[str, tuple[tuple, object, str]], what: str,
            **attrs):
    """An xarray Dataset: coords {dim: (values, unit)}, data {name: (dims, values, unit)}, each
    with attrs["units"]; attrs: the Dataset's own (text and numbers only, so it writes to netCDF)."""
    xr = need("xarray", what)
    return xr.Dataset({n: (dims, np.asarray(v), {"units": u}) for n, (dims, v, u) in data.items()},
                      coords={n: (n, np.asarray(v), {"units": u}) for n, (v, u) in coords.items()},
                      attrs=attrs)
