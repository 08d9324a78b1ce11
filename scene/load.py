"""Scenes: find and read a TOML file, apply `--set` overrides, validate, and resolve the parameters to SI.

Pure Python (no sympy): derive/ and runtime/ both use it. A scene names a physical set-up
(docs/contract.md, "Scenes"; every plate kind's keys: docs/scenes.md); every problem is reported as
one `SceneError` line that names the key, says what is wrong and how to fix it. The keys this
checks are scene/keys.py, the `--set` language scene/overrides.py.

Parameter conventions (docs/contract.md, "Physics conventions"): U = m g z - mu n.B, B = -grad(phi).
The thesis's thin annulus (thesis eq. 2.2.11) has Phi0 = 2 pi rho z (...), and only mu*rho enters
the dynamics; `plate.murho` keeps that parametrisation. In SI the annulus is a dipole layer of
density D (A) with rho = mu0 D / (4 pi). The plate kinds live in the registry scene/plates/.
"""
from __future__ import annotations

import hashlib
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import tomllib

from . import plates
from .checks import SceneError, check_keys, number
from .keys import (
    ABSOLUTE_ZERO, COORDINATES, FIELD_KEYS, FRICTION_KEYS, KEY_BOUNDS, LAUNCH_KEYS, MODEL_KEYS, NEEDS,
    PRODUCTION_KEYS, REFERENCE_KEYS, SCENE_KEYS, T_REF, TEMPERATURE_KEY, TILT_KEYS_NAMES, TOP_KEYS, UNITS,
)
from .overrides import apply_override
from .paths import SCENES_DIR
from .plates.base import Key
from .checks_budget import check_size
from .quantity import convert_scene

__all__ = ["Scene", "SceneError", "find_scene_file", "load_scene", "validate"]

_NAME = re.compile(r"[A-Za-z0-9_-]+\Z")
MAX_NAME = 100     # characters: <name>-<hash> and .<name>.new-<pid>-* must fit a file name (255)


def _names(keys: tuple[Key, ...]) -> set[str]:
    return {k.name for k in keys}


# ---------------------------------------------------------------- the scene

@dataclass
class Scene:
    """A validated scene with its parameters resolved to SI."""

    name: str
    path: Path | None
    data: dict
    params: dict[str, float]            # m, g, A, C, mu, plate parameters (SI), friction rates
    notes: list[str] = field(default_factory=list)
    field_factor: float = 1.0           # the plate's field at `temperature` over its field at T_REF
    overrides: tuple[str, ...] = ()     # the --set strings load_scene applied (with path: the recipe)

    @property
    def plate_kind(self) -> str:
        return self.data["plate"]["kind"]

    @property
    def needs(self) -> tuple[str, ...]:
        return tuple(self.data["model"]["needs"])

    @property
    def friction(self) -> bool:
        """The scene declares air friction (a decay time in [top]): its full model is dissipative."""
        return any(k in self.data["top"] for k in FRICTION_KEYS)

    @property
    def tilted(self) -> bool:
        """The full model has a base tilt's terms (gravity along a tilted vector, parameters
        base_tilt, base_tilt_azimuth): the scene declares plate.tilt, or top.moment_offset (an
        imperfect apparatus gets both, so that one route serves it: runtime/physics/tilted_*)."""
        return any(k in self.data["plate"] for k in TILT_KEYS_NAMES) or self.offset or self.askew

    @property
    def offset(self) -> bool:
        """The scene declares top.moment_offset: the moment at r + d n in the full model."""
        return "moment_offset" in self.data["top"]

    @property
    def askew(self) -> bool:
        """The scene declares top.moment_tilt: the moment tilted from the axis, fixed in the body."""
        return "moment_tilt" in self.data["top"]

    @property
    def coordinates(self) -> str:
        return self.data["model"]["coordinates"]

    @property
    def length_scale(self) -> float:
        """The plate's characteristic length (its largest length parameter, compound parts
        included; 1.0 for a plate without lengths): scene/plates/__init__.py `length_scale`."""
        return plates.length_scale(self.data["plate"], self.params)

    @property
    def field_spec(self) -> dict:
        return dict(self.data["field"])

    def canonical(self) -> str:
        """The scene as canonical JSON (sorted keys, numbers spelled one way: spelled_alike, so
        that 200 and 200.0 are one scene)."""
        return json.dumps(spelled_alike(self.data), sort_keys=True, separators=(",", ":"))

    def scene_hash(self) -> str:
        return hashlib.sha256(self.canonical().encode()).hexdigest()


EXACT_INT = 2 ** 53       # every integer below this is a double exactly


def spelled_alike(node):
    """The data with every number written one way: a float with an integral value (200.0) as the
    integer (200), so that how a number is spelled in the TOML never makes another scene (the
    input hash here, the scene hash of scene/load.py). Booleans stay booleans."""
    if isinstance(node, dict):
        return {k: spelled_alike(v) for k, v in node.items()}
    if isinstance(node, list):
        return [spelled_alike(v) for v in node]
    if isinstance(node, float) and node.is_integer() and abs(node) < EXACT_INT:
        return int(node)
    return node


def _exists(path: Path) -> bool:
    try:
        return path.exists()
    except (OSError, ValueError):   # a NUL byte, a name too long for the file system
        return False


def find_scene_file(name_or_path: str | Path) -> Path:
    """The scene file of a name in scenes/ or a path; SceneError when there is none."""
    p = Path(name_or_path)
    shown = str(name_or_path) if len(str(name_or_path)) <= 80 else str(name_or_path)[:77] + "..."
    if p.suffix == ".toml" or _exists(p):
        if not _exists(p):
            raise SceneError(f"scene file {shown!r} does not exist: give a path to a .toml file or "
                             f"a name from {SCENES_DIR}")
        if not p.is_file():
            raise SceneError(f"scene {shown!r} is not a file (a directory?): give a path to a .toml "
                             f"file or a name from {SCENES_DIR}")
        return p
    candidate = SCENES_DIR / f"{name_or_path}.toml"
    if _exists(candidate):
        return candidate
    known = ", ".join(sorted(q.stem for q in SCENES_DIR.glob("*.toml")))
    raise SceneError(f"unknown scene {shown!r}: use one of {known} or a path to a .toml file")


def load_scene(name_or_path: str | Path, overrides: list[str] | tuple[str, ...] = ()) -> Scene:
    """Read, override, validate and resolve a scene (docs/contract.md, "Scenes")."""
    path = find_scene_file(name_or_path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML ({exc}); fix the syntax") from None
    except RecursionError:
        raise SceneError(f"{path}: nested too deeply for a scene (tables or arrays within "
                         "thousands of others): flatten it") from None
    except UnicodeDecodeError:
        raise SceneError(f"{path}: not a text file (not UTF-8): give a TOML scene") from None
    except OSError as exc:
        raise SceneError(f"{path}: cannot be read ({exc.strerror}): check the path and its "
                         "permissions") from None
    for text in overrides:
        apply_override(data, text)
    data.setdefault("name", path.stem)
    scene = validate(data, path)
    scene.overrides = tuple(overrides)
    return scene


def friction_rates(top: dict, needs) -> dict[str, float]:
    """k = 1 / tau for every FRICTION_KEYS decay time of [top] (0 for one not given), or {} when
    the scene declares none. Friction acts on the full model only: the reduced model lies on the
    invariant set (thesis 3.2.1), where a slowing top never falls."""
    given = [k for k in FRICTION_KEYS if k in top]
    if not given:
        return {}
    if "full" not in needs:
        raise SceneError(f"top.{given[0]} needs the full model: add \"full\" to model.needs (the "
                         "reduced model keeps the top upright on the axis, where a slowing top never "
                         "falls), or remove the decay time")
    rates = {}
    for key, name in FRICTION_KEYS.items():
        tau = number(top, key, "top", positive=True, required=False)
        rates[name] = 0.0 if tau is None else 1.0 / tau    # number() bounds tau's magnitude
    return rates


def _reference_value(ref: dict, key: str) -> None:
    """A [reference] value: a positive number or [value, uncertainty] (z_stable, flight_time), or a
    range [low, high] (spin_interval, mass_window)."""
    v = ref[key]
    pair = isinstance(v, list) and len(v) == 2 and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)
    if key in ("spin_interval", "mass_window"):
        if not (pair and 0 < v[0] <= v[1]):
            raise SceneError(f"reference.{key} = {v!r}: give a range [low, high] of positive numbers, "
                             f"e.g. {key} = [1.0, 2.0]")
    elif isinstance(v, list):
        if not (pair and v[0] > 0 and v[1] >= 0):
            raise SceneError(f"reference.{key} = {v!r}: give a positive number or [value, uncertainty], "
                             f"e.g. {key} = [0.15, 0.01]")
    else:
        number(ref, key, "reference", positive=True)


def validate(data: dict, path: Path | None = None) -> Scene:
    """Check every key and resolve the parameters; raises SceneError on the first problem. A value
    with a unit ("51.5 g") becomes its SI number first (scene/quantity.py)."""
    warned = convert_scene(data)
    check_keys(data, _names(SCENE_KEYS) | {"top", "plate", "field", "model", "reference", "launch", "production"},
               "scene")
    for table, keys in (("launch", LAUNCH_KEYS), ("production", PRODUCTION_KEYS)):
        if not isinstance(data.get(table, {}), dict):
            raise SceneError(f"{table} = ... is not a section: write [{table}] with its keys")
        check_keys(data.get(table, {}), _names(keys), table)
    if data.get("units", "SI") not in UNITS:
        raise SceneError(f"units = {data['units']!r}: use one of {list(UNITS)}")
    ref = data.get("reference", {})
    if not isinstance(ref, dict):
        raise SceneError("reference = ... is not a section: write [reference] with its keys")
    check_keys(ref, _names(REFERENCE_KEYS), "reference")
    if not isinstance(ref.get("source", ""), str):
        raise SceneError("reference.source must be text, e.g. source = \"thesis\"")
    for key in ("z_stable", "spin_interval", "mass_window", "flight_time"):
        if key in ref:
            _reference_value(ref, key)
    for section in ("top", "plate"):
        if section not in data or not isinstance(data[section], dict):
            raise SceneError(f"the scene has no [{section}] section: add it (see docs/contract.md)")
    data.setdefault("field", {"order": 2})
    data.setdefault("model", {})
    for section in ("field", "model"):
        if not isinstance(data[section], dict):
            raise SceneError(f"{section} = {data[section]!r} is not a section: write [{section}] "
                             f"with its keys (see docs/contract.md)")
    g = number(data, "g", "", positive=True, default=9.81)
    data["g"] = g

    top = data["top"]
    check_keys(top, _names(TOP_KEYS), "top")
    m = number(top, "mass", "top", positive=True)
    A = number(top, "A", "top", positive=True)
    C = number(top, "C", "top", positive=True)
    if C > 2 * A * (1 + 1e-12):
        raise SceneError(f"top.C = {C} exceeds 2*top.A = {2 * A}: no rigid body has an axial moment "
                         "larger than the sum of the two transverse ones; check which is A and which C")
    moment = number(top, "moment", "top", nonzero=True, required=False)

    temp = temperature_factors(data)
    resolved = plates.resolve({k: v for k, v in data["plate"].items()
                               if k != TEMPERATURE_KEY.name and k not in TILT_KEYS_NAMES}, moment)
    notes = list(warned)      # a bare number that reads as grams or millimetres meant
    mu = resolved.pop("mu", moment)
    if resolved.pop("moment_nominal", None) is not None:
        notes.append("top.moment not given: only mu*rho (plate.murho) is physical; fields are "
                     "reported for a nominal moment, top.moment = -1 in the scene's units")
    if mu is None:
        raise SceneError("[top] moment is missing: add `moment = <A m^2>` (signed, along the axis)")

    fld = data["field"]
    check_keys(fld, _names(FIELD_KEYS), "field")
    if "order" in fld:
        order = fld["order"]
        if isinstance(order, bool) or not isinstance(order, int) or order < 2 or order % 2:
            raise SceneError(f"field.order = {order!r} must be an even integer >= 2 "
                             "(the expansion of thesis eq. 2.2.6 has even powers of r only)")
        if order > 12:
            raise SceneError(f"field.order = {order} is above 12: use field.tolerance instead")
    elif "tolerance" in fld:
        number(fld, "tolerance", "field", positive=True)
        number(fld, "radius", "field", positive=True)
    else:
        raise SceneError("[field] needs `order` (even, >= 2) or `tolerance` and `radius`")
    check_size(data["plate"], fld)            # every derivation bounded (scene/checks_budget.py)

    model = data["model"]
    check_keys(model, _names(MODEL_KEYS), "model")
    tilt = base_tilt(data["plate"])
    offset = magnet_offset(top)
    askew = magnet_tilt(top)
    needs = model.setdefault("needs", ["full", "linear"] if tilt or offset or askew
                             else ["reduced", "full", "linear"])
    if not isinstance(needs, list) or not needs or any(n not in NEEDS for n in needs):
        raise SceneError(f"model.needs = {needs!r}: give a non-empty list drawn from {list(NEEDS)}")
    for key, given, why in (
            ("plate.tilt", tilt, "breaks the axial symmetry: the 4-D reduced model (thesis 3.2.12, "
             "the top on the axis) does not exist for a tilted base"),
            ("top.moment_offset", offset, "is modelled in the full model only: the reduced model "
             "(thesis 3.2.12) is not derived with it"),
            ("top.moment_tilt", askew, "breaks the top's own symmetry: the 4-D reduced model "
             "(thesis 3.2.12, the spin a constant of the motion) does not exist for a moment off "
             "the axis")):
        if given and "reduced" in needs:
            if "full" not in needs:
                raise SceneError(f"{key} {why}; give model.needs = [\"full\", \"linear\"] or "
                                 f"remove {key}")
            needs = [n for n in needs if n != "reduced"]
            notes.append(f"{key}: no reduced model (it {why.split(': ')[0]}): the full model only")
    if "linear" in needs and "full" not in needs:
        raise SceneError("model.needs has 'linear' without 'full': the linearisation is that of the "
                         "full model; add \"full\"")
    model["needs"] = [n for n in NEEDS if n in needs]  # canonical order
    coords = model.setdefault("coordinates", "tait-bryan")
    if coords not in COORDINATES:
        raise SceneError(f"model.coordinates = {coords!r}: use one of {list(COORDINATES)}")

    name = data.get("name")
    if not isinstance(name, str) or not _NAME.match(name):
        raise SceneError(f"name = {name!r}: use letters, digits, '-' and '_' only")
    if len(name) > MAX_NAME:
        raise SceneError(f"name = {name[:20]!r}... is {len(name)} characters long (the limit is "
                         f"{MAX_NAME}: it names folders): give a shorter `name = ...` or file name")

    # U = -mu n.B and B is linear in the plate's strength (thesis 2.2.1): the two magnets' thermal
    # factors enter the dynamics as one factor on mu; `field` shows B times the plate's factor
    params = {"m": m, "g": g, "A": A, "C": C, "mu": float(mu) * temp[0] * temp[1]}
    params.update({f"plate_{k}": float(v) for k, v in resolved.items()})
    params.update(friction_rates(top, model["needs"]))
    params.update(tilt or ({"base_tilt": 0.0, "base_tilt_azimuth": 0.0} if offset or askew else {}))
    params.update(offset)
    params.update(askew)
    if data.get("temperature", T_REF) != T_REF:
        notes.append(f"at {data['temperature']:g} degC: plate field x {temp[0]:.6g}, top moment x "
                     f"{temp[1]:.6g} of their {T_REF:g} degC values")
    return Scene(name=name, path=path, data=data, params=params, notes=notes, field_factor=temp[0])


def base_tilt(plate: dict) -> dict[str, float]:
    """{base_tilt, base_tilt_azimuth} (rad) from the TILT_KEYS of [plate], or {} when neither is
    given (a level base: the model without the tilt's terms)."""
    if not any(k in plate for k in TILT_KEYS_NAMES):
        return {}
    if "tilt" not in plate:
        raise SceneError("plate.tilt_azimuth without plate.tilt: give the tilt (rad) too, e.g. "
                         "plate.tilt = 0.001")
    tilt = number(plate, "tilt", "plate")
    if not KEY_BOUNDS["plate.tilt"].admits(tilt):
        raise SceneError(f"plate.tilt = {tilt:g} rad: give the base's tilt from level, "
                         f"{KEY_BOUNDS['plate.tilt'].text} (its direction is plate.tilt_azimuth)")
    az = number(plate, "tilt_azimuth", "plate", default=0.0)
    return {"base_tilt": tilt, "base_tilt_azimuth": az}


def magnet_offset(top: dict) -> dict[str, float]:
    """{moment_offset} (m) from top.moment_offset, or {} when not given (derive/spec.py refuses
    it over a plate without axial symmetry)."""
    if "moment_offset" not in top:
        return {}
    return {"moment_offset": number(top, "moment_offset", "top")}


def magnet_tilt(top: dict) -> dict[str, float]:
    """{moment_tilt} (rad) from top.moment_tilt, or {} when not given."""
    if "moment_tilt" not in top:
        return {}
    b = number(top, "moment_tilt", "top")
    if not KEY_BOUNDS["top.moment_tilt"].admits(b):
        raise SceneError(f"top.moment_tilt = {b:g} rad: give the moment's angle from the symmetry "
                         f"axis, {KEY_BOUNDS['top.moment_tilt'].text} (a larger one is a top with the "
                         "moment the other way)")
    return {"moment_tilt": b}


def temperature_factors(data: dict) -> tuple[float, float]:
    """(plate, top) factors of the remanence at the scene's temperature T: 1 + alpha (T - T_REF),
    alpha the temperature_coefficient of [plate] and of [top] (linear model of the data sheets)."""
    T = data.get("temperature", T_REF)
    if isinstance(T, bool) or not isinstance(T, (int, float)) or not T == T or abs(T) == float("inf"):
        raise SceneError(f"temperature = {T!r} is not a number: give degrees Celsius, e.g. 28")
    if T < ABSOLUTE_ZERO:
        raise SceneError(f"temperature = {T:g} degC is below absolute zero ({ABSOLUTE_ZERO} degC): "
                         "give degrees Celsius")
    out = []
    for section in ("plate", "top"):
        alpha = number(data[section], TEMPERATURE_KEY.name, section, default=0.0)
        if not -0.1 <= alpha <= 0.1:
            raise SceneError(f"{section}.{TEMPERATURE_KEY.name} = {alpha:g} is not a relative change "
                             "per kelvin: magnets have about -0.002 (ferrite) to -0.0012 (NdFeB)")
        f = 1.0 + alpha * (float(T) - T_REF)
        if not f > 0:
            raise SceneError(f"at temperature = {T:g} degC the {section} magnet's remanence factor "
                             f"1 + {alpha:g} (T - {T_REF:g}) = {f:.3g} is not positive: the linear "
                             "temperature model does not reach that far")
        out.append(f)
    return out[0], out[1]
