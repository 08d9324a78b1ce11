"""A compound plate: the sum of parts, each a [[plate.parts]] table of any kind (a rectangle, another
compound), optionally with `sign = -1` (the part taken away: a hole is a part of the opposite sign)."""
from __future__ import annotations

from ..checks import SceneError, check_keys
from ..checks_budget import check_nesting
from .base import Context, Key, PlateKind

SIGN = "sign"      # a part's own key beside its kind's: +1 or -1 (the part's field times it)
# The derivation budget: the parts of one plate, nested compounds' parts counted. Each part is
# derived on its own (measured at field.order 2: a ring magnet about 4 s, a holed rectangle
# 8-18 s; 10 holed rectangles took 167 s, 40 did not end in 300 s), so a plate of more parts is
# refused before any derivation, with its count; levitron/from_magpylib.py takes as many sources.
MAX_PARTS = 16


def leaf_parts(table: dict) -> int:
    """The parts of a plate table that are not themselves compound, at every depth (1 for a plate
    of another kind)."""
    parts = table.get("parts") if table.get("kind") == "compound" else None
    if not isinstance(parts, list):
        return 1
    return sum(leaf_parts(p) if isinstance(p, dict) else 1 for p in parts)


def resolve(table: dict, ctx: Context) -> dict:
    """Part i's parameters are named p<i>_<name> (its sign, where given, p<i>_sign); a part's "mu" /
    "moment_nominal" (murho without a top moment) become the scene's."""
    where = ctx.where
    parts = table.get("parts")
    if not isinstance(parts, list) or not parts or not all(isinstance(p, dict) for p in parts):
        raise SceneError(f"[{where}] needs a non-empty list of parts: add [[{where}.parts]] tables")
    check_nesting({**table, "kind": "compound"}, where)      # before leaf_parts' recursion
    n = leaf_parts({**table, "kind": "compound"})
    if n > MAX_PARTS:
        raise SceneError(f"[{where}] has {n} parts (nested compounds' counted), more than the derivation "
                         f"budget of {MAX_PARTS}: each part is derived on its own (10 holed rectangles take "
                         "about 3 minutes); merge parts (one ring for magnets of one radius) or take fewer")
    allowed = sorted(k for k, kind in ctx.kinds.items() if kind.can_be_part)
    out: dict = {}
    for i, part in enumerate(parts):
        pw = f"{where}.parts[{i}]"
        kind = ctx.kinds.get(part.get("kind")) if isinstance(part.get("kind"), str) else None
        if kind is None or not kind.can_be_part:
            raise SceneError(f"{pw}.kind = {part.get('kind')!r}: a part must be one of "
                             f"{', '.join(allowed)}")
        check_keys(part, kind.allowed | {SIGN}, pw)
        res = dict(kind.resolve({k: v for k, v in part.items() if k != SIGN}, ctx.at(pw)))
        if SIGN in part:
            sign = part[SIGN]
            if isinstance(sign, bool) or sign not in (1, -1):
                raise SceneError(f"{pw}.sign = {sign!r}: give 1 (the part adds its field) or -1 (it "
                                 "is taken away, e.g. a hole)")
            res[SIGN] = float(sign)
        for special in ("mu", "moment_nominal"):
            if special in res:
                out[special] = res.pop(special)
        out.update({f"p{i}_{k}": v for k, v in res.items()})
    return out


KIND = PlateKind(
    name="compound",
    doc="the sum of parts, each a [[plate.parts]] table of any kind (a rectangle, another compound); "
        "part i's parameters are plate_p<i>_<name>, and `sign = -1` on a part takes it away (a "
        "hole: the part with the opposite magnetisation). With a rectangle among the parts the full "
        "model uses the rectangles' exact 3-D field plus the other parts' expansion to field.order",
    keys=(Key("parts", "", "list of [[plate.parts]] tables, each with its own kind and keys, and "
              "optionally `sign` (1 or -1, default 1)"),),
    resolve=resolve,
    has_parts=True,
    example='kind = "compound"\n\n[[plate.parts]]\nkind = "ring_magnet"\nr_out = 0.06\nr_in = 0.03\n'
            'thickness = 0.02\nremanence = 0.39\n\n[[plate.parts]]\nkind = "loop"\nradius = 0.02\n'
            'current = -50.0',
    outline=None,          # drawn as its parts' (has_parts)
    quarter_turn=None,     # its parts' symmetry (has_parts)
    exact_field=None,      # its parts' (has_parts)
)
