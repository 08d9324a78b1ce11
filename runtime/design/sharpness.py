"""How sharp a design is: the objective at plus and minus a maker's tolerance of each varied key.

An optimum says where the best design is, not how far a maker may miss it. A launch-odds optimum
can be a knife edge: half a millimetre of bore, or one per cent of remanence, moves the hover
height z_s (m g + mu Phi_2(z_s) = 0, thesis 3.3.2) and with it the spin window (the ray cubic,
thesis 3.3.13-3.3.19) out from under the launch spread. So, after every design:

1. **A tolerance per key** (`tolerances`): given (`«tolerance» plate.hole=0.0005`), else a
   default by the key's unit (scene/keys.py, scene/plates/*.py): a length 0.1 mm, a mass 0.1 g
   (ABSOLUTE), a magnet's strength (remanence, magnetisation, murho, moment, current) 1 % of its
   value (RELATIVE), any other key, and every key of a dimensionless scene (which has no
   millimetre), OTHER = 0.2 % of its value.
2. **Two evaluations a key** (`probe`): the objective at x - tol e_k and x + tol e_k, the others
   at the optimum; the sensitivity is the central difference (f+ - f-) / (2 tol) (near an
   interior optimum small: the loss, f0 - min(f-, f+), is what the verdict reads). For the launch
   odds both are Monte Carlos on the first min(n, SIDE_N) of the design's fresh draws, paired
   with the optimum's (launch_design.paired_side: the request already pinned, in the design's
   kept pool): 2 per key.
3. **The verdict** (`knife_edge`): a knife edge where either side loses more than LAUNCH_LOSS
   (half) of the optimum's launch odds, or more than OBJECTIVE_LOSS (10 %) of another objective;
   a side where the top cannot hover (no objective) is a knife edge too.
4. **The ridge** (two or three keys, `ridge`): which combination of keys the design cannot tell
   apart. The launch odds depend on the keys only through the hover state the hand launches
   into: its height z_s and its spin window (sigma_lo, sigma_hi) at z_s (thesis 3.3.2,
   3.3.15-3.3.19; the hand is fixed). So the matrix J[q, k] = relative change of the hover
   quantity q per tolerance of key k (`hover_matrix`: tol_k dq/dx_k / q, the exact float routes, no
   Monte Carlo) is the keys' first-order effect; two keys whose columns are parallel within
   PARALLEL_DEG degrees move the design along one ridge (only their combination is designed: e.g. plate.murho and
   top.moment enter only as mu rho, thesis 2.2.11), and the smallest right singular vector of J is
   the near-null direction, the move (in tolerances of each key) that changes the hover state
   least. The same matrix serves the IPOPT objectives, which are functions of the same state.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import Units, sig

ABSOLUTE = {"m": 1e-4, "kg": 1e-4, "rad": 1e-3}          # SI: 0.1 mm, 0.1 g, 1 mrad
RELATIVE = {"T": 0.01, "A/m": 0.01, "J m": 0.01, "A m^2": 0.01, "A": 0.01, "T m": 0.01}
OTHER = 0.002                  # relative: any other key, every key of a dimensionless scene
LAUNCH_LOSS = 0.5              # a knife edge: a side loses more than this fraction of the odds
OBJECTIVE_LOSS = 0.1           # ... or of another objective
DERIVATIVE_STEP = 0.01         # the ridge's slopes: central differences over +- this fraction of a tolerance
PARALLEL_DEG = 10.0            # two keys' effects on the hover state this parallel: one ridge
HOVER = ("z_s", "sigma_lo", "sigma_hi")
METHOD = ("the objective at the optimum +- a tolerance of each key, the others held (2 evaluations a key; "
          "launch odds paired with the optimum on its fresh draws); ridge: the keys' relative effects on z_s, "
          "sigma_lo and sigma_hi (runtime/design/sharpness.py)")


def key_unit(scene, key: str) -> str:
    """The SI unit a scene key is written in ("" where none is declared)."""
    from levitron.scene.keys import SCENE_KEYS, TILT_KEYS, TOP_KEYS
    from levitron.scene.plates import KINDS
    section, _, name = key.partition(".")
    table = {"top": TOP_KEYS, "": SCENE_KEYS}.get(section if name else "", ())
    if section == "plate":
        kind = KINDS.get((scene.data.get("plate") or {}).get("kind"))
        table = (*(kind.keys if kind else ()), *TILT_KEYS)
    return next((k.unit for k in table if k.name == (name or section)), "")


def default_tolerance(scene, key: str, value: float) -> float:
    """The documented default tolerance of a key at `value` (module docstring, step 1)."""
    unit = key_unit(scene, key)
    if Units.of_scene(scene).si:
        if unit in ABSOLUTE:
            return ABSOLUTE[unit]
        if unit in RELATIVE:
            return RELATIVE[unit] * abs(value)
    return OTHER * abs(value) or OTHER


def parse_tolerance(texts: Sequence[str]) -> dict[str, float]:
    """The command line's KEY=VALUE words -> {key: value}; UserError saying how to write one."""
    out = {}
    for text in texts:
        key, sep, value = text.partition("=")
        try:
            out[key.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep or not key.strip():
            raise UserError(f"«tolerance» {text!r}: write KEY=VALUE in the key's SI unit, e.g. plate.hole=0.0005")
    return out


def tolerances(scene, optimum: Mapping[str, float], given: Mapping[str, float] | None) -> dict[str, float]:
    """Each varied key's tolerance: given, else the default at the optimum; UserError for a given
    key that is not varied or a tolerance that is not a positive number."""
    if given is not None and not isinstance(given, Mapping):
        raise UserError("«tolerance» must map varied keys to numbers, e.g. {'plate.hole': 0.0005}")
    given = dict(given or {})
    for k, v in given.items():
        if k not in optimum:
            raise UserError(f"«tolerance» {k}: not a «vary» key; give one of {', '.join(optimum)}")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
            raise UserError(f"«tolerance» {k}={v!r}: give a positive number in the key's SI unit")
    return {k: float(given[k]) if k in given else default_tolerance(scene, k, x) for k, x in optimum.items()}


def knife_edge(optimum: float, minus: float | None, plus: float | None, launch: bool) -> bool:
    """Whether a side loses more than LAUNCH_LOSS of the odds (launch) or OBJECTIVE_LOSS of the
    objective (others); a side without a value (no hover, no interval) is a knife edge."""
    if minus is None or plus is None:
        return True
    loss = LAUNCH_LOSS if launch else OBJECTIVE_LOSS
    return min(minus, plus) < optimum - loss * abs(optimum)


def probe(f: Callable[[tuple], float | None], optimum: Mapping[str, float], value: float,
          tols: Mapping[str, float], launch: bool) -> dict[str, dict]:
    """The per-key block (module docstring, steps 2-3): f at -tol and +tol of each key."""
    keys, x0 = list(optimum), [float(v) for v in optimum.values()]
    out = {}
    for k, key in enumerate(keys):
        side = []
        for sign in (-1, 1):
            x = list(x0)
            x[k] += sign * tols[key]
            try:
                side.append(f(tuple(x)))
            except UserError:           # the scene is not valid there (a radius below 0): no value
                side.append(None)
        lo, hi = side
        out[key] = {"tolerance": tols[key], "at_minus": lo, "at_plus": hi,
                    "sensitivity": None if lo is None or hi is None else (hi - lo) / (2 * tols[key]),
                    "knife_edge": knife_edge(value, lo, hi, launch)}
    return out


def ridge(keys: Sequence[str], J) -> dict | None:
    """The near-null direction of J (hover quantities x keys, relative effect of one tolerance of
    each key) and the key pairs whose columns are parallel within PARALLEL_DEG (one ridge); None
    for one key or a zero column."""
    J = np.asarray(J, float)
    norms = np.linalg.norm(J, axis=0)
    if len(keys) < 2 or J.ndim != 2 or not np.all(norms > 0) or not np.all(np.isfinite(J)):
        return None
    C = J / norms
    pairs = []
    for i in range(len(keys)):
        for j in range(i + 1, len(keys)):
            angle = math.degrees(math.acos(min(1.0, abs(float(C[:, i] @ C[:, j])))))
            if angle <= PARALLEL_DEG:
                pairs.append({"keys": [keys[i], keys[j]], "angle_deg": angle})
    _, s, vt = np.linalg.svd(J, full_matrices=True)
    d = vt[-1] * (1 if vt[-1][np.argmax(np.abs(vt[-1]))] > 0 else -1)
    return {"quantities": list(HOVER), "effects": {k: [float(v) for v in J[:, i]] for i, k in enumerate(keys)},
            "direction": {k: float(v) for k, v in zip(keys, d)},
            "singular_values": [float(v) for v in s], "one_ridge": pairs,
            "method": "smallest right singular vector of the keys' relative effects on the hover state, "
                      "per tolerance (direction in tolerances of each key)"}


def hover_state(model, keys: Sequence[str], x) -> np.ndarray | None:
    """(z_s, sigma_lo, sigma_hi) of the scene re-resolved at the keys' values x, by the exact float
    routes (differentiable.starts); None where the top does not hover with a spin window."""
    from levitron.runtime.design.scene_keys import pvector, with_values
    from levitron.runtime.physics.stability import differentiable as diffable
    p = pvector(model.param_names, with_values(model.scene, dict(zip(keys, map(float, x)))))
    st = diffable.starts(model, p)
    return None if st.z_s is None or st.spin is None else np.array([st.z_s, *st.spin])


def hover_matrix(model, optimum: Mapping[str, float], tols: Mapping[str, float]) -> np.ndarray | None:
    """J[q, k] = tol_k (dq/dx_k) / q: the relative change of the hover state per tolerance of key k
    (module docstring, step 4), the derivative by a central difference over +-DERIVATIVE_STEP
    tol_k (a local slope: at a full tolerance the top may already fall, as at a knife edge)."""
    keys, x0 = list(optimum), [float(v) for v in optimum.values()]
    q0 = hover_state(model, keys, x0)
    if q0 is None:
        return None
    cols = []
    for k, key in enumerate(keys):
        side = []
        for sign in (-1, 1):
            x = list(x0)
            x[k] += sign * DERIVATIVE_STEP * tols[key]
            side.append(hover_state(model, keys, x))
        if side[0] is None or side[1] is None:
            return None
        cols.append((side[1] - side[0]) / (2 * DERIVATIVE_STEP * q0))
    return np.array(cols).T


def sharpness(f, model, varies, optimum: Mapping[str, float], value: float, given, launch: bool) -> dict:
    """The `sharpness` block: per key (probe), and for two or three keys the ridge (None where the
    hover state cannot be computed, e.g. over a tilted base)."""
    tols = tolerances(model.scene, optimum, given)
    block = {"objective": value, "keys": probe(f, optimum, value, tols, launch), "ridge": None,
             "rule": f"knife edge: a side below {1 - (LAUNCH_LOSS if launch else OBJECTIVE_LOSS):g} x the optimum",
             "method": METHOD}
    if len(optimum) > 1:
        try:
            J = hover_matrix(model, optimum, tols)
        except (UserError, ValueError, RuntimeError, ArithmeticError):
            J = None
        block["ridge"] = None if J is None else ridge(list(optimum), J)
    return block


def ridge_groups(pairs: Sequence[dict]) -> list[tuple[list[str], float]]:
    """The keys the parallel pairs join (connected), each group with its largest angle."""
    groups: list[tuple[list[str], float]] = []
    for pair in pairs:
        a, b = pair["keys"]
        hit = [g for g in groups if a in g[0] or b in g[0]]
        keys = [k for g in hit for k in g[0]] + [a, b]
        merged = (list(dict.fromkeys(keys)), max([pair["angle_deg"], *(g[1] for g in hit)]))
        groups = [g for g in groups if g not in hit] + [merged]
    return groups


def tolerance_text(scene, key: str, tol: float, u: Units) -> str:
    """A key's tolerance in the scene's units: "0.1 mm", "0.1 g", "0.0118 T"."""
    unit = key_unit(scene, key) if scene is not None else ""
    return u.length(tol, 3) if unit == "m" else u.mass(tol, 3) if unit == "kg" else u.value(tol, unit, 3)


def sharpness_lines(block: dict | None, u: Units, scene=None, name: str = "launch-odds", unit: str = "") -> list[str]:
    """The plain view: one line a key ("a knife edge: ..." where it is one), one a ridge."""
    if not block:
        return []
    launch = name in ("launch-odds", "yield")      # probabilities, in %
    scale, end = (100, " %") if launch else (1, f" {u.unit(unit)}".rstrip() if u.unit(unit) else "")
    show = lambda v: "none" if v is None else sig(scale * v, 3 if launch else 4)   # noqa: E731
    what = "the odds" if name == "launch-odds" else name
    out = []
    for key, r in block["keys"].items():
        lo, hi = sorted([r["at_minus"], r["at_plus"]], key=lambda v: -math.inf if v is None else v)
        tol = tolerance_text(scene, key, r["tolerance"], u)
        head, verb = ("a knife edge", "takes") if r["knife_edge"] else ("sharpness", "gives")
        shown = show(lo) + end if show(lo) == show(hi) else f"{show(lo)}-{show(hi)}{end}"
        out.append(f"{head}: {key} +-{tol} {verb} {what} {'to ' if r['knife_edge'] else ''}{shown} "
                   f"(at the optimum {show(block['objective'])}{end})")
    rid = block.get("ridge")
    if rid:
        for group, angle in ridge_groups(rid["one_ridge"]):
            names = ", ".join(group[:-1]) + f" and {group[-1]}"
            out.append(f"{names} move along one ridge (their effects on the hover height and spin window lie "
                       f"within {sig(angle, 2)} degrees): only their combination is designed")
        d = ", ".join(f"{sig(v, 2)} x {tolerance_text(scene, k, block['keys'][k]['tolerance'], u)} of {k}"
                      for k, v in rid["direction"].items())
        out.append(f"the direction that changes the hover state least: {d}")
    return out
