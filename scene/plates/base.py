"""What one plate kind declares on the scene side (pure Python, no sympy).

A kind is one module of scene/plates/ defining `KIND = PlateKind(...)`:

- `keys`: the scene keys it allows, each with its unit and a one-line doc (docs/scenes.md is
  generated from them: `python -m levitron.scene.plates.docs`);
- `resolve(table, ctx) -> {name: SI value}`: validation and the parameters by the names of the
  plate's symbols (Scene.params holds them as `plate_<name>`, compound part i as `plate_p<i>_<name>`);
  it may add "mu" (the plate fixes the moment, `murho`) and "moment_nominal";
- `decisions`: every number-valued choice that changes the generated code, declared here next to
  the builder that branches on it (derive/plate_fields/<kind>.py calls the same `Decision.test`),
  so that the input hash (scene/inputs.py) covers it;
- `length_keys`: the resolved parameters that are lengths (the plate's length scale);
- `units`: the SI units of its other resolved parameters ("rho": "T m", ...), where they have one;
- `example`: a TOML [plate] table that validates (tests/scene/test_plate_registry.py checks it);
- `outline(table) -> dict | None`: the base as the set-up drawing shows it (runtime/simulate/setup_shape.py),
  {"kind": "ring" | "rect" | "loop", lengths as the scene writes them}, or None: no outline (an
  expression plate; a compound plate is drawn as its parts'). Every kind says it (no default), so a
  new kind is never drawn without a base by oversight;
- `quarter_turn(params, sign) -> (part, turned)`: for a kind without axial symmetry, the part (its
  resolved parameters, the strengths times `sign`) and what a quarter turn about z makes of it, as
  comparable tuples (scene/plates/symmetry.py); None: a quarter turn leaves the kind as it is
  (axisymmetric). Every kind says it too.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from ..checks import SceneError, number, one_of
from ..constants import MU0


@dataclass(frozen=True)
class Key:
    """One scene key of a plate kind: name, unit ("" if dimensionless or not a number), doc."""

    name: str
    unit: str
    doc: str


@dataclass(frozen=True)
class Decision:
    """A structural decision: `test(table) -> bool` on a validated [plate] table; its value is part
    of the input hash. `doc` says what the generated code does differently when it holds."""

    name: str
    doc: str
    test: Callable[[dict], bool]


@dataclass(frozen=True)
class Context:
    """What a resolver needs beside its table: the top's moment (None if not given), the table's
    place in the scene (for messages) and the registry (for a compound plate's parts)."""

    moment: float | None
    where: str = "plate"
    kinds: Mapping[str, PlateKind] = field(default_factory=dict)

    def at(self, where: str) -> Context:
        return Context(self.moment, where, self.kinds)


@dataclass(frozen=True)
class PlateKind:
    name: str
    doc: str
    keys: tuple[Key, ...]
    resolve: Callable[[dict, Context], dict]
    example: str
    outline: Callable[[dict], dict | None] | None        # the drawn base; None: none (no default)
    quarter_turn: Callable[[Mapping[str, float], float], tuple] | None   # None: axisymmetric (no default)
    # the model's field of a table of this kind is exact (no expansion about the axis, thesis eq. 2.2.6,
    # to truncate); None: always the expansion (no default)
    exact_field: Callable[[dict], bool] | None
    decisions: tuple[Decision, ...] = ()
    length_keys: tuple[str, ...] = ()
    units: Mapping[str, str] = field(default_factory=dict)     # resolved name -> SI unit (not lengths)
    can_be_part: bool = True      # may be one of a compound plate's [[plate.parts]]
    has_parts: bool = False       # is a compound plate: its parts carry their own decisions, lengths

    @property
    def allowed(self) -> frozenset[str]:
        return frozenset({"kind"} | {k.name for k in self.keys})


def drawn_length(table: dict, key: str, default: float = 0.0) -> float:
    """A length of a [plate] table as an outline draws it (scene units), `default` where it is absent."""
    v = table.get(key, default)
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else default


# ---------------------------------------------------------------- shared resolvers

# the SI units of the parameters the shared resolvers below give: a thin layer's strength, a
# magnet's magnetisation
STRENGTH_UNITS = {"rho": "T m", "magnetization": "A/m"}

STRENGTH_KEYS = (
    Key("murho", "J m", "mu * rho of thesis eq. 2.2.11 (the thesis's parametrisation), the only product the "
        "dynamics sees; with it top.moment may be left out"),
    Key("dipole_density", "A", "dipole density D of the layer (SI), rho = mu0 D / (4 pi); needs "
        "top.moment"),
)

MAGNETIZATION_KEYS = (
    Key("magnetization", "A/m", "uniform magnetisation M along +z"),
    Key("remanence", "T", "remanence Br instead of M (M = Br / mu0)"),
)


def strength_rho(table: dict, ctx: Context) -> dict:
    """The dipole-layer strength rho (T m) of a thin plate from `murho` or `dipole_density`
    (docs/contract.md, physics conventions: rho = mu0 D / (4 pi))."""
    where = ctx.where
    has_murho, has_d = "murho" in table, "dipole_density" in table
    if has_murho == has_d:
        raise SceneError(f"[{where}] needs exactly one of `murho` (thesis units, mu*rho) or "
                         "`dipole_density` (A, SI): give one of them")
    if has_murho:
        murho = number(table, "murho", where, nonzero=True)
        if ctx.moment is None:
            # Only mu*rho enters the dynamics; a nominal |mu| = 1 A m^2 with the sign of an
            # upright top over a field that points up (docs/contract.md) keeps rho's sign physical.
            return {"mu": -1.0, "rho": -murho, "moment_nominal": 1.0}
        return {"rho": murho / ctx.moment}
    if ctx.moment is None:
        raise SceneError(f"[{where}] dipole_density needs [top] moment (A m^2): add it")
    dens = number(table, "dipole_density", where, nonzero=True)
    return {"rho": MU0 * dens / (4.0 * math.pi)}


def magnetization(table: dict, ctx: Context) -> float:
    """M (A/m) from `magnetization` or `remanence` (M = Br / mu0)."""
    key = one_of(table, ("magnetization", "remanence"), ctx.where, "A/m, or T with M = Br/mu0")
    value = number(table, key, ctx.where, nonzero=True)
    return value if key == "magnetization" else value / MU0
