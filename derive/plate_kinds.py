"""Scene validation and SI resolution of every plate kind (pure Python, no sympy).

derive/scene.py builds its PLATE_KINDS table from PLATE_KIND_TABLE below. Each resolver takes the
[plate] table (or one of its [[plate.parts]]) and the top's moment, and returns the SI parameters by the names that
derive/plates_extra.py gives the plate's symbols (Scene.params then holds them as `plate_<name>`):

  loop         radius, current (A) | center_field (T: B at the centre = mu0 I / (2 a))
               -> a, current
  ring_magnet  r_out, r_in (default 0 = solid cylinder), thickness, magnetization (A/m) |
               remanence (T: M = Br / mu0); top face at z = 0    -> r_out, [r_in], thickness, magnetization
  rectangle    side | side_x and side_y; thickness (default 0); a block (thickness > 0) needs
               magnetization | remanence, a thin layer (thickness = 0) murho | dipole_density
               -> side_x, side_y, thickness, magnetization | side_x, side_y, rho
  expression   phi0 = "..." | bz = "..." (a formula in z and the names of [plate.params]),
               [plate.params] name = number                          -> the params
  compound     [[plate.parts]], each a table of one of the other kinds (no rectangle)
               -> p<i>_<name> for part i

Formulas are only checked for type and length here; derive parses them (derive/expr_parse.py) and
reports a bad formula as a one-line SceneError naming plate.phi0 / plate.bz.
"""
from __future__ import annotations

import re

_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
# Names a parameter may not take (functions and constants of derive/expr_parse.py, and z).
RESERVED_NAMES = frozenset({
    "z", "pi", "E", "sqrt", "exp", "log", "sin", "cos", "tan", "asin", "acos", "atan", "atan2",
    "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "abs", "Abs"})
MAX_FORMULA = 2000


def _scene():
    from . import scene  # imported lazily: scene.py imports this module while it loads
    return scene


def _num(table, key, where, **kw):
    return _scene()._number(table, key, where, **kw)


def _err(msg: str) -> Exception:
    return _scene().SceneError(msg)


def _check(table: dict, allowed: set, where: str) -> None:
    _scene()._check_keys(table, allowed, where)


def _one_of(table: dict, keys: tuple[str, str], where: str, hint: str) -> str:
    present = [k for k in keys if k in table]
    if len(present) != 1:
        raise _err(f"[{where}] needs exactly one of `{keys[0]}` or `{keys[1]}` ({hint}): give one")
    return present[0]


# ---------------------------------------------------------------- thin plates (for parts)

ANNULUS_KEYS = {"kind", "radius", "hole", "murho", "dipole_density"}
DISK_KEYS = {"kind", "radius", "murho", "dipole_density"}


def resolve_annulus(table: dict, moment, where: str = "plate") -> dict:
    a = _num(table, "radius", where, positive=True)
    w = _num(table, "hole", where, default=0.0)
    if w < 0:
        raise _err(f"{where}.hole = {w} is negative: give 0 <= hole < radius")
    if w >= a:
        raise _err(f"{where}.hole = {w} is not smaller than {where}.radius = {a}: "
                   "make the hole smaller than the plate")
    out = dict(_scene()._strength_rho(table, moment, where))
    out.update({"a": a, "w": w})
    return out


def resolve_disk(table: dict, moment, where: str = "plate") -> dict:
    out = dict(_scene()._strength_rho(table, moment, where))
    out["a"] = _num(table, "radius", where, positive=True)
    return out


# ---------------------------------------------------------------- new kinds

LOOP_KEYS = {"kind", "radius", "current", "center_field"}


def resolve_loop(table: dict, moment, where: str = "plate") -> dict:
    """A circular current loop in z = 0; B at its centre is mu0 I / (2 a) (Jackson eq. 5.40)."""
    a = _num(table, "radius", where, positive=True)
    key = _one_of(table, ("current", "center_field"), where, "A, or T at the centre")
    if key == "current":
        cur = _num(table, "current", where, nonzero=True)
    else:
        cur = 2 * a * _num(table, "center_field", where, nonzero=True) / _scene().MU0
    return {"a": a, "current": cur}


RING_KEYS = {"kind", "r_out", "r_in", "thickness", "magnetization", "remanence"}


def _magnetization(table: dict, where: str) -> float:
    key = _one_of(table, ("magnetization", "remanence"), where, "A/m, or T with M = Br/mu0")
    value = _num(table, key, where, nonzero=True)
    return value if key == "magnetization" else value / _scene().MU0


def resolve_ring_magnet(table: dict, moment, where: str = "plate") -> dict:
    """Axially magnetised ring (r_in > 0) or solid cylinder (r_in = 0), top face in z = 0."""
    r_out = _num(table, "r_out", where, positive=True)
    r_in = _num(table, "r_in", where, default=0.0)
    if r_in < 0 or r_in >= r_out:
        raise _err(f"{where}.r_in = {r_in} must satisfy 0 <= r_in < r_out = {r_out}: "
                   "make the inner radius smaller (0 for a solid cylinder)")
    out = {"r_out": r_out, "thickness": _num(table, "thickness", where, positive=True),
           "magnetization": _magnetization(table, where)}
    if r_in > 0:
        out["r_in"] = r_in
    return out


RECT_KEYS = {"kind", "side", "side_x", "side_y", "thickness", "magnetization", "remanence",
             "murho", "dipole_density"}


def resolve_rectangle(table: dict, moment, where: str = "plate") -> dict:
    """A uniformly magnetised rectangular plate centred on the axis: block or thin layer."""
    if "side" in table:
        if "side_x" in table or "side_y" in table:
            raise _err(f"[{where}] has `side` and `side_x`/`side_y`: give `side` (a square) or both "
                       "`side_x` and `side_y`")
        sx = sy = _num(table, "side", where, positive=True)
    else:
        if "side_x" not in table or "side_y" not in table:
            raise _err(f"[{where}] needs `side` (a square) or both `side_x` and `side_y` (m): add them")
        sx = _num(table, "side_x", where, positive=True)
        sy = _num(table, "side_y", where, positive=True)
    t = _num(table, "thickness", where, default=0.0)
    if t < 0:
        raise _err(f"{where}.thickness = {t} is negative: give 0 (a thin layer) or the thickness (m)")
    if t > 0:
        for bad in ("murho", "dipole_density"):
            if bad in table:
                raise _err(f"{where}.{bad} is for a thin layer (thickness = 0): give magnetization "
                           "or remanence for a block")
        return {"side_x": sx, "side_y": sy, "thickness": t,
                "magnetization": _magnetization(table, where)}
    for bad in ("magnetization", "remanence"):
        if bad in table:
            raise _err(f"{where}.{bad} needs a thickness > 0 (a block): add `thickness`, or give "
                       "murho / dipole_density for a thin layer")
    out = dict(_scene()._strength_rho(table, moment, where))
    out.update({"side_x": sx, "side_y": sy})
    return out


EXPR_KEYS = {"kind", "phi0", "bz", "params"}


def resolve_expression(table: dict, moment, where: str = "plate") -> dict:
    """phi0 or bz as a formula string; [plate.params] name -> number."""
    key = _one_of(table, ("phi0", "bz"), where, "the on-axis potential or on-axis field, in z")
    text = table[key]
    if not isinstance(text, str) or not text.strip():
        raise _err(f"{where}.{key} must be a formula in quotes, e.g. {key} = \"b*z/sqrt(z**2 + c**2)\"")
    if len(text) > MAX_FORMULA:
        raise _err(f"{where}.{key} is {len(text)} characters long: the limit is {MAX_FORMULA}")
    params = table.get("params", {})
    if not isinstance(params, dict):
        raise _err(f"{where}.params must be a table of name = number: write [{where}.params]")
    out = {}
    for name in sorted(params):
        if not _IDENT.match(name) or name in RESERVED_NAMES:
            raise _err(f"{where}.params.{name}: not a usable name (letters, digits, '_', starting "
                       f"with a letter; not z or a function name): rename it")
        out[name] = _num(params, name, f"{where}.params")
    return out


COMPOUND_KEYS = {"kind", "parts"}

_PART_KINDS = {
    "annulus": (ANNULUS_KEYS, resolve_annulus),
    "disk": (DISK_KEYS, resolve_disk),
    "loop": (LOOP_KEYS, resolve_loop),
    "ring_magnet": (RING_KEYS, resolve_ring_magnet),
    "expression": (EXPR_KEYS, resolve_expression),
}


def resolve_compound(table: dict, moment, where: str = "plate") -> dict:
    """A sum of parts; part i's parameters are named p<i>_<name>."""
    parts = table.get("parts")
    if not isinstance(parts, list) or not parts or not all(isinstance(p, dict) for p in parts):
        raise _err(f"[{where}] needs a non-empty list of parts: add [[{where}.parts]] tables")
    out: dict = {}
    for i, part in enumerate(parts):
        pw = f"{where}.parts[{i}]"
        kind = part.get("kind")
        if kind not in _PART_KINDS:
            raise _err(f"{pw}.kind = {kind!r}: a part must be one of {', '.join(sorted(_PART_KINDS))}")
        keys, resolve = _PART_KINDS[kind]
        _check(part, keys, pw)
        res = dict(resolve(part, moment, pw))
        for special in ("mu", "moment_nominal"):
            if special in res:
                out[special] = res.pop(special)
        out.update({f"p{i}_{k}": v for k, v in res.items()})
    return out


# kind -> (allowed keys, resolver(table, moment) -> dict, doc): every plate kind of a scene
PLATE_KIND_TABLE = {
    "annulus": (ANNULUS_KEYS, resolve_annulus, "thin annulus, thesis eq. 2.2.11"),
    "disk": (DISK_KEYS, resolve_disk, "thin disk (annulus without hole)"),
    "loop": (LOOP_KEYS, resolve_loop, "circular current loop in z = 0"),
    "ring_magnet": (RING_KEYS, resolve_ring_magnet,
                    "axially magnetised ring or cylinder magnet, top face in z = 0"),
    "rectangle": (RECT_KEYS, resolve_rectangle,
                  "uniformly magnetised rectangular plate (block or thin layer), exact 3-D field"),
    "expression": (EXPR_KEYS, resolve_expression, "on-axis phi0 or bz given as a formula"),
    "compound": (COMPOUND_KEYS, resolve_compound, "sum of parts ([[plate.parts]])"),
}
