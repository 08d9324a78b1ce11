"""Scenes: read a TOML file, apply `--set` overrides, validate, and resolve the parameters to SI.

Pure Python (no sympy): both derive/ and runtime/ use it. A scene names a physical set-up
(docs/contract.md, "Scenes"; every plate kind's keys: docs/scenes.md); every problem is reported as
one `SceneError` line that names the key, says what is wrong and how to fix it.

Parameter conventions (docs/contract.md, "Physics conventions"): U = m g z - mu n.B, B = -grad(phi).
The thesis's thin annulus (thesis eq. 2.2.11) has Phi0 = 2 pi rho z (...), and only mu*rho enters
the dynamics; `plate.murho` keeps that parametrisation. In SI the annulus is a dipole layer of
density D (A) with rho = mu0 D / (4 pi). The plate kinds live in the registry derive/plates/.
"""
from __future__ import annotations

import hashlib
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import tomli_w
import tomllib

from . import plates
from .checks import SceneError, check_keys, number
from .constants import MU0
from .paths import SCENES_DIR
from .plates.base import Key

__all__ = ["MU0", "SCENES_DIR", "Scene", "SceneError", "find_scene_file", "load_scene",
           "override_text", "parse_override", "validate"]


NEEDS = ("reduced", "full", "linear")
COORDINATES = ("tait-bryan", "euler-zxz")
UNITS = ("SI", "dimensionless")
T_REF = 20.0            # degC: the reference temperature of the temperature coefficients
ABSOLUTE_ZERO = -273.15

# The keys of every section but [plate] (whose keys are the plate kinds', derive/plates/); the
# contract docs/scenes.md is generated from these and the registry (`python -m levitron.derive.plates.docs`).
SCENE_KEYS = (
    Key("name", "", "the scene's name (letters, digits, '-', '_'; default: the file's stem)"),
    Key("description", "", "free text"),
    Key("g", "m/s^2", "gravity (default 9.81; 1 in a dimensionless scene)"),
    Key("temperature", "degC", f"the temperature of the magnets (default {T_REF:g} degC, the "
        "reference of the temperature coefficients; `--temperature` on every command)"),
    Key("units", "", f"how numbers are shown to a person, one of {list(UNITS)} (default: \"SI\" "
        "when 9 <= g <= 10.5, else \"dimensionless\"); never how they are computed"),
)
REFERENCE_KEYS = (
    Key("source", "", "where the stated values come from (e.g. \"thesis\"), shown beside them"),
    Key("z_stable", "m", "a stated height of the vertically stable equilibrium, shown beside ours "
        "(a number, or [value, uncertainty])"),
    Key("spin_interval", "rad/s", "a stated spin interval of stability, [low, high]"),
    Key("mass_window", "kg", "a stated range of masses that hover, [lightest, heaviest]"),
    Key("flight_time", "s", "a stated flight time in air (a number, or [value, uncertainty])"),
)
TEMPERATURE_KEY = Key("temperature_coefficient", "1/K", "relative change of the magnet's "
                      "remanence per kelvin from 20 degC (ferrite about -0.002, NdFeB about -0.0012; "
                      "default 0); in [top] and in [plate]")
TOP_KEYS = (
    Key("mass", "kg", "mass m of the top"),
    Key("A", "kg m^2", "transverse moment of inertia"),
    Key("C", "kg m^2", "axial moment of inertia (C <= 2 A)"),
    Key("moment", "A m^2", "magnetic moment mu along the symmetry axis, signed (mu < 0: upright "
        "over a field that points up); may be left out with plate.murho"),
    Key("spin_decay_time", "s", "air friction: the e-folding time tau of the spin of a free top, "
        "omega_3(t) = omega_3(0) exp(-t / tau) (measure it with a tachometer); any decay time makes "
        "the full model dissipative (derive/friction.py)"),
    Key("tilt_decay_time", "s", "air friction: the e-folding time of the transverse (tumbling) "
        "angular velocity of a free top (default: none)"),
    Key("translation_decay_time", "s", "air friction: the e-folding time of the velocity of the "
        "centre of mass of a free top (default: none)"),
    TEMPERATURE_KEY,
    Key("moment_offset", "m", "the magnet's centre along the symmetry axis from the centre of mass "
        "(positive towards the moment's end of the axis n; default: none, the magnet at the centre "
        "of mass): the moment feels the field at r + d n (derive/mechanics.py); the scene then "
        "has no reduced model"),
)

# The base's tilt (issue 27): keys of [plate] that every plate kind takes; they put gravity along a
# tilted vector in the full model (derive/mechanics.py), as runtime parameters base_tilt and
# base_tilt_azimuth (their values never change the generated code; their presence does).
TILT_KEYS = (
    Key("tilt", "rad", "the base's tilt from level (0 <= tilt < pi/2): gravity in the plate's frame is "
        "g (sin tilt cos az, sin tilt sin az, -cos tilt), az = tilt_azimuth; breaks the axial "
        "symmetry, so the scene has no reduced model (derive/mechanics.py)"),
    Key("tilt_azimuth", "rad", "the downhill direction in the plate's frame, from +x towards +y "
        "(default 0: downhill is +x, the base tilted about the y axis); needs tilt"),
)
TILT_PARAMS = {"tilt": "base_tilt", "tilt_azimuth": "base_tilt_azimuth"}

# decay-time key of [top] -> the runtime parameter it sets, the rate 1 / tau (0 where not given)
FRICTION_KEYS = {"spin_decay_time": "k_spin", "tilt_decay_time": "k_tilt",
                 "translation_decay_time": "k_trans"}
FIELD_KEYS = (
    Key("order", "", "even order in r of the Laplace expansion, 2..12 (default 2)"),
    Key("tolerance", "", "instead of order: the largest relative error of the expanded field, "
        "with radius"),
    Key("radius", "m", "the distance from the axis within which tolerance must hold"),
)
LAUNCH_KEYS = tuple(Key(k, u, d) for k, u, d in (
    ("spin", "rad/s", "the launch spin: \"normal:MEAN,SD\", \"uniform:LO,HI\" or a number"),
    ("tilt", "rad", "the tilt of the axis (same forms)"),
    ("tilt_azimuth", "rad", "the direction of the tilt (same forms)"),
    ("offset", "m", "the offset of the centre of mass along x (same forms)"),
    ("velocity", "m/s", "the horizontal velocity along y (same forms)"),
    ("mass", "", "the relative deviation of the mass (same forms)"),
    ("strength", "", "the relative deviation of the magnets' strength (same forms)"),
    ("temperature", "degC", "the magnets' temperature (same forms)"),
    ("base_tilt", "rad", "the base's tilt from level, sampled per launch (same forms; needs plate.tilt)"),
    ("base_tilt_azimuth", "rad", "the base's downhill direction, sampled per launch (same forms; "
     "needs plate.tilt)"),
    ("success_time", "s", "a launch succeeds when the top floats at least this long"),
    ("t_end", "s", "the run length of each launch"),
    ("n", "", "the number of launches"),
    ("seed", "", "the seed of the sampler"),
))
MODEL_KEYS = (
    Key("needs", "", f"what derive emits, a list drawn from {list(NEEDS)} (default all; "
        "\"linear\" needs \"full\")"),
    Key("coordinates", "", f"angles of the full model, one of {list(COORDINATES)} (default "
        "\"tait-bryan\", regular at the upright top; \"euler-zxz\" as in the thesis)"),
)
TILT_KEYS_NAMES = tuple(k.name for k in TILT_KEYS)
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
        return any(k in self.data["plate"] for k in TILT_KEYS_NAMES) or self.offset

    @property
    def offset(self) -> bool:
        """The scene declares top.moment_offset: the moment at r + d n in the full model."""
        return "moment_offset" in self.data["top"]

    @property
    def coordinates(self) -> str:
        return self.data["model"]["coordinates"]

    @property
    def length_scale(self) -> float:
        """The plate's characteristic length (its largest length parameter, compound parts
        included; 1.0 for a plate without lengths): derive/plates/__init__.py `length_scale`."""
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
    input hash here, the scene hash of derive/scene.py). Booleans stay booleans."""
    if isinstance(node, dict):
        return {k: spelled_alike(v) for k, v in node.items()}
    if isinstance(node, list):
        return [spelled_alike(v) for v in node]
    if isinstance(node, float) and node.is_integer() and abs(node) < EXACT_INT:
        return int(node)
    return node


_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")   # tab allowed
_BARE_WORD = re.compile(r"[^\"'\\]*\Z")


def parse_override(text: str) -> tuple[list[str], Any]:
    """`section.key=value` -> (["section", "key"], value); value parsed as one TOML value (or a
    bare word without quotes, e.g. plate.kind=disk). The one reader of overrides: the command
    line's --set and the API's keys (`override_text`) both come through it. A newline or another
    control character is refused (TOML would read the rest as more keys, and drop or change them)."""
    if not isinstance(text, str):
        raise SceneError(f"--set {text!r} is not text: write --set section.key=value")
    shown = text if len(text) <= 80 else text[:77] + "..."
    bad = _CONTROL.search(text)
    if bad:
        raise SceneError(f"--set {shown!r} holds a control character ({bad.group()!r}, e.g. a newline): "
                         "give one key and one value on one line (\\n inside a quoted TOML string)")
    if "=" not in text:
        raise SceneError(f"--set {shown!r} has no '=': write --set section.key=value")
    key, raw = text.split("=", 1)
    path = [p.strip() for p in key.strip().split(".")]
    if not all(path):
        raise SceneError(f"--set {shown!r}: the key {key!r} is malformed; write e.g. top.mass=0.03")
    try:
        parsed = tomllib.loads(f"v = {raw.strip()}")
    except RecursionError:
        raise SceneError(f"--set {shown!r}: the value is nested too deeply: give a number, text "
                         "or a flat list") from None
    except tomllib.TOMLDecodeError:
        if not raw.strip() or not _BARE_WORD.match(raw.strip()):
            raise SceneError(f"--set {shown!r}: the value is not a TOML value; quote a string as "
                             "TOML does, e.g. --set 'plate.phi0=\"z/sqrt(z**2 + 1)\"'") from None
        return path, raw.strip()  # a bare word, e.g. --set plate.kind=disk
    if set(parsed) != {"v"}:
        raise SceneError(f"--set {shown!r}: the value must be one TOML value")
    return path, parsed["v"]


def _toml_value(value: Any, key: str) -> str:
    """One TOML value on one line, written by tomli_w (arrays inline)."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v, key) for v in value) + "]"
    if isinstance(value, dict):
        raise SceneError(f"{key}: a table is not one value: give each key of it separately "
                         f"({key}.<name>=...)")
    try:
        return tomli_w.dumps({"v": value})[len("v = "):].strip()
    except TypeError:
        raise SceneError(f"{key} = {value!r}: a {type(value).__name__} is not a scene value: give a "
                         "number, text, true/false or a list of them") from None


def override_text(key: str, value: Any) -> str:
    """The `--set` text of scene key `key` (e.g. "top.mass") set to `value`, written by a TOML
    writer, never by string formatting: quotes, backslashes and newlines in a value stay inside
    it. `parse_override(override_text(k, v))` gives back (k.split("."), v)."""
    if not isinstance(key, str) or not re.fullmatch(r"[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*", key):
        raise SceneError(f"scene key {key!r} is not a key: write section.key, e.g. top.mass")
    return f"{key}={_toml_value(value, key)}"


def apply_override(data: dict, text: str) -> None:
    """Apply one `--set section.key=value` to the scene's table. A list of tables (a compound
    plate's [[plate.parts]]) is entered by its 0-based index: plate.parts.1.radius=0.02."""
    keys, value = parse_override(text)
    node: Any = data
    for k in keys[:-1]:
        if isinstance(node, list):
            node = node[_index(text, k, node)]
        else:
            node = node.setdefault(k, {})
        if not isinstance(node, (dict, list)):
            raise SceneError(f"--set {text!r}: {k!r} is not a section")
    if isinstance(node, list):
        raise SceneError(f"--set {text!r}: {keys[-2]!r} is a list of tables: name a key inside "
                         f"one of them, e.g. {'.'.join(keys[:-1])}.0.<key>=...")
    node[keys[-1]] = value


def _index(text: str, k: str, items: list) -> int:
    if not k.isdigit() or int(k) >= len(items):
        raise SceneError(f"--set {text!r}: {k!r} is not an index of a list of {len(items)} tables; "
                         f"use 0..{len(items) - 1}")
    return int(k)


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
    return validate(data, path)


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
    """Check every key and resolve the parameters; raises SceneError on the first problem."""
    check_keys(data, _names(SCENE_KEYS) | {"top", "plate", "field", "model", "reference", "launch"},
               "scene")
    if not isinstance(data.get("launch", {}), dict):
        raise SceneError("launch = ... is not a section: write [launch] with its keys")
    check_keys(data.get("launch", {}), _names(LAUNCH_KEYS), "launch")
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
    notes = []
    mu = resolved.pop("mu", moment)
    if resolved.pop("moment_nominal", None) is not None:
        notes.append("top.moment not given: only mu*rho (plate.murho) is physical; fields are "
                     "reported for a nominal moment of -1 A m^2")
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

    model = data["model"]
    check_keys(model, _names(MODEL_KEYS), "model")
    tilt = base_tilt(data["plate"])
    offset = magnet_offset(top)
    needs = model.setdefault("needs", ["full", "linear"] if tilt or offset else ["reduced", "full", "linear"])
    if not isinstance(needs, list) or not needs or any(n not in NEEDS for n in needs):
        raise SceneError(f"model.needs = {needs!r}: give a non-empty list drawn from {list(NEEDS)}")
    for key, given, why in (
            ("plate.tilt", tilt, "breaks the axial symmetry: the 4-D reduced model (thesis 3.2.12, "
             "the top on the axis) does not exist for a tilted base"),
            ("top.moment_offset", offset, "is modelled in the full model only: the reduced model "
             "(thesis 3.2.12) is not derived with it")):
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
    params.update(tilt or ({"base_tilt": 0.0, "base_tilt_azimuth": 0.0} if offset else {}))
    params.update(offset)
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
    if not 0 <= tilt < math.pi / 2:
        raise SceneError(f"plate.tilt = {tilt:g} rad: give the base's tilt from level, 0 <= tilt < "
                         "pi/2 (its direction is plate.tilt_azimuth)")
    az = number(plate, "tilt_azimuth", "plate", default=0.0)
    return {"base_tilt": tilt, "base_tilt_azimuth": az}


def magnet_offset(top: dict) -> dict[str, float]:
    """{moment_offset} (m) from top.moment_offset, or {} when not given (derive/spec.py refuses
    it over a plate without axial symmetry)."""
    if "moment_offset" not in top:
        return {}
    return {"moment_offset": number(top, "moment_offset", "top")}


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
