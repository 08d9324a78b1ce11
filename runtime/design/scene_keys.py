"""The one mapping from scene keys (`top.mass`, `plate.hole`) to the generated parameter vector p.

Users name numbers by their scene keys; the generated functions take p (manifest order: m, g, A, C,
mu, plate_...). The mapping is never written down a second time: it is the scene resolver's own
(scene/load.py `validate` and the plate registry scene/plates/), applied by re-resolving the
scene with the key changed. Its derivative, which CasADi needs, comes from a structure every
resolver has: each parameter is a constant times a product of powers of the key values
(plate_a = radius, plate_rho = murho / moment, plate_magnetization = remanence / mu0,
plate_current = 2 radius center_field / mu0, ...). `KeyMap` measures those integer powers by
re-resolving at two values of each key and then checks the monomial law against re-resolution at
every corner of the box to 1e-12; a key whose parameters do not follow it is refused. So
p(x) = p_ref * prod_k (x_k / x_ref_k)^E[j, k] is exact, and values at any point are checked
against re-resolution again where they are reported.

A box must keep the model's structure (scene/plates decisions, e.g. ring_magnet `hollow`) and
every corner must be a valid scene (scene.load.validate: masses, inertias, radii > 0,
hole < radius, C <= 2 A); these constraints are linear in the keys, so the whole box is valid.
"""
from __future__ import annotations

import copy
import itertools
import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from levitron.scene import plates
from levitron.scene.load import Scene, SceneError, validate

from levitron.runtime.errors import UserError
from levitron.runtime.ui.validate import number_text

RTOL = 1e-12


def _path(key: str) -> list[str]:
    if not isinstance(key, str):
        raise UserError(f"{key!r} is not a scene key: write it as text, section.key, e.g. 'top.mass'")
    parts = key.split(".")
    if not key or not all(parts):
        raise UserError(f"{key!r} is not a scene key: write it as section.key, e.g. top.mass or "
                        "plate.hole")
    return parts


def _child(node, k: str, key: str):
    """node[k] of a table, or item k (0-based) of a list of tables (a compound plate's parts)."""
    if isinstance(node, dict) and k in node:
        return node[k]
    if isinstance(node, list) and k.isdigit() and int(k) < len(node):
        return node[int(k)]
    raise UserError(f"the scene has no number at {key}: vary a key the scene sets "
                    "(see docs/scenes.md; a compound plate's parts are plate.parts.<i>.<key>), "
                    "or add it with «set»")


def key_value(data: dict, key: str) -> float:
    """The number at `key` in a scene's data (UserError if there is none)."""
    node = data
    for k in _path(key):
        node = _child(node, k, key)
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        raise UserError(f"{key} = {node!r} is not a number: vary a numeric scene key")
    return float(node)


def with_values(scene: Scene, values: dict[str, float]) -> Scene:
    """The scene re-resolved with the given keys set (scene.load.validate); UserError if invalid."""
    data = copy.deepcopy(scene.data)
    for key, v in values.items():
        node = data
        path = _path(key)
        for k in path[:-1]:
            node = _child(node, k, key)
        node[path[-1]] = float(v)
    try:
        return validate(data, scene.path)
    except SceneError as exc:
        raise UserError(str(exc)) from None


def pvector(names: Sequence[str], scene: Scene) -> np.ndarray:
    return np.array([scene.params[n] for n in names], dtype=float)


@dataclass(frozen=True)
class Vary:
    """A varied scene key and its bounds (the key's unit, docs/scenes.md)."""

    key: str
    lo: float
    hi: float

    @classmethod
    def parse(cls, text: str) -> Vary:
        """'KEY=LO:HI' -> Vary; UserError saying how to write it."""
        key, sep, rng = text.partition("=")
        lo, sep2, hi = rng.partition(":")
        try:
            lo_v, hi_v = number_text(lo.strip()), number_text(hi.strip())
        except ValueError:
            lo_v = hi_v = math.nan
        if not (sep and sep2):
            raise UserError(f"«vary» {text!r}: write KEY=LO:HI with numbers, e.g. plate.hole=0.01:0.05")
        return cls.checked(key.strip(), lo_v, hi_v, f"«vary» {text!r}")

    @classmethod
    def checked(cls, key, lo, hi, where: str) -> Vary:
        """The one check of a varied key's box, for the CLI's --vary and the API's {key: (lo, hi)}:
        a key, finite numbers, LO < HI, not straddling 0."""
        numbers_ok = all(isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)
                         for v in (lo, hi))
        if not (isinstance(key, str) and key.strip() and numbers_ok):
            raise UserError(f"{where}: write KEY=LO:HI with numbers, e.g. plate.hole=0.01:0.05")
        lo_v, hi_v = float(lo), float(hi)
        if not lo_v < hi_v:
            raise UserError(f"{where}: LO must be below HI")
        if lo_v < 0 < hi_v:
            raise UserError(f"{where}: the bounds must not straddle 0 (a scene number keeps "
                            "its sign): give LO >= 0 or HI <= 0")
        return cls(key.strip(), lo_v, hi_v)


STRUCTURE_SECTIONS = ("field", "model")    # their numbers change the generated code, not p


class KeyMap:
    """p(x) for the varied keys x of one scene and model (module docstring)."""

    def __init__(self, scene: Scene, names: Sequence[str], varies: Sequence[Vary]):
        keys = [v.key for v in varies]
        if len(set(keys)) != len(keys):
            raise UserError(f"a key is varied twice: {', '.join(keys)}")
        self.scene, self.names, self.varies = scene, list(names), list(varies)
        for v in varies:
            if v.key.split(".")[0] in STRUCTURE_SECTIONS:
                raise UserError(f"{v.key} is structure (docs/contract.md: [field] and [model] shape the "
                                "generated model), not a runtime parameter: it has no derivative and "
                                "cannot be varied; set it in the scene instead")
            key_value(scene.data, v.key)
        self.x_ref = np.array([0.5 * (v.lo + v.hi) for v in varies])
        ref = self.resolve(self.x_ref)
        self.p_ref = pvector(self.names, ref)
        self.E = np.zeros((len(self.names), len(varies)))
        for k, v in enumerate(varies):
            x = self.x_ref.copy()
            x[k] = v.hi
            p = pvector(self.names, self.resolve(x))
            self.E[:, k] = [self._power(v.key, n, a, b, self.x_ref[k], v.hi)
                            for n, a, b in zip(self.names, self.p_ref, p)]
        decided = plates.decisions(scene.data["plate"])
        for corner in itertools.product(*[(v.lo, v.hi) for v in varies]):
            sc = self.resolve(np.array(corner))
            if plates.decisions(sc.data["plate"]) != decided:
                raise UserError(f"at {self.describe(corner)} the plate's structure changes "
                                f"({plates.decisions(sc.data['plate'])} instead of {decided}): keep "
                                "the bounds on one side of the structural decision")
            self.check(np.array(corner), pvector(self.names, sc))

    def resolve(self, x) -> Scene:
        try:
            return with_values(self.scene, {v.key: float(xi) for v, xi in zip(self.varies, x)})
        except UserError as exc:
            raise UserError(f"at {self.describe(x)} the scene is not valid ({exc}): narrow the "
                            "«vary» bounds") from None

    def describe(self, x) -> str:
        return ", ".join(f"{v.key} = {float(xi):.6g}" for v, xi in zip(self.varies, x))

    @staticmethod
    def _power(key: str, name: str, a: float, b: float, xa: float, xb: float) -> float:
        if a == b:
            return 0.0
        if a == 0 or b == 0 or (a > 0) != (b > 0):
            raise UserError(f"parameter {name} does not scale as a power of {key}: this key cannot "
                            "be varied")
        e = math.log(b / a) / math.log(xb / xa)
        if abs(e - round(e)) > 1e-9:
            raise UserError(f"parameter {name} does not scale as an integer power of {key}: this key "
                            "cannot be varied")
        return float(round(e))

    def p(self, x) -> np.ndarray:
        """p(x) by the monomial law (floats)."""
        r = np.asarray(x, float) / self.x_ref
        return self.p_ref * np.prod(r[None, :] ** self.E, axis=1)

    def p_casadi(self, x):
        """p(x) as a CasADi expression of the key values x (SX/MX column)."""
        import casadi as ca
        out = []
        for j in range(len(self.names)):
            term = ca.SX(float(self.p_ref[j])) if isinstance(x, ca.SX) else ca.MX(float(self.p_ref[j]))
            for k in range(len(self.varies)):
                if self.E[j, k]:
                    term = term * (x[k] / self.x_ref[k]) ** self.E[j, k]
            out.append(term)
        return ca.vertcat(*out)

    def check(self, x, p_true) -> None:
        """The monomial law agrees with re-resolution at x (RTOL), else a UserError."""
        pred = self.p(x)
        bad = np.abs(pred - p_true) > RTOL * np.maximum(np.abs(p_true), 1e-300)
        if bad.any():
            j = int(np.argmax(bad))
            raise UserError(f"parameter {self.names[j]} is not a product of powers of the varied "
                            f"keys at {self.describe(x)}: vary other keys")

    def exact(self, x) -> tuple[Scene, np.ndarray]:
        """The re-resolved scene at x and its p, checked against the monomial law."""
        sc = self.resolve(x)
        p = pvector(self.names, sc)
        self.check(x, p)
        return sc, p


def grid_points(varies: Sequence[Vary], n: int) -> list[tuple[float, ...]]:
    """The n^k points of the --vary box's grid, n per key, its ends included (the verification grid)."""
    axes = [np.linspace(v.lo, v.hi, n) for v in varies]
    return list(itertools.product(*axes))


def bounds_hit(varies: Sequence[Vary], x, rtol: float = 1e-6) -> dict[str, str]:
    """{key: "lower" | "upper"} for each key within rtol of its box's span of a --vary bound (IPOPT
    keeps its iterates ~1e-9 of the span inside the box: bound_relax_factor, mu)."""
    out = {}
    for v, xi in zip(varies, x):
        tol = rtol * (v.hi - v.lo)
        if xi <= v.lo + tol:
            out[v.key] = "lower"
        elif xi >= v.hi - tol:
            out[v.key] = "upper"
    return out
