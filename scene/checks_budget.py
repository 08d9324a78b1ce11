"""Every derivation bounded: the budgets a plate is held to before anything is derived, each said in
its one-line SceneError with the number that exceeded it.

* nesting: a compound inside a compound inside ... at most MAX_DEPTH levels, counted without
  recursion (a plate nested 400 deep was a RecursionError in the input hash's copy of the scene);
* parts: at most MAX_PARTS leaf parts (scene/plates/compound.py, which checks it);
* size: the field terms the derivation makes. Each leaf part brings its on-axis potential and its
  z-derivatives Phi_0 ... Phi_{order+2}: the expansion to field.order (thesis eq. 2.2.6) takes Phi_k
  up to k = order for the potential, order + 1 for B = -grad phi (eq. 2.2.7) and order + 2 for the
  force, so a plate derives parts x (order + 3) terms, at most MAX_TERMS. With field.tolerance the
  order is chosen at derivation, up to MAX_ORDER (derive/field_order.py), and the count takes that.
  MAX_TERMS is MAX_PARTS parts at order 2, the parts budget's own calibration (holed rectangles,
  10 in about 3 minutes). Derivations of compounds of annuli, measured on a loaded machine: 16
  parts 18 s at order 2 and 112 s at order 12, 4 parts 32 s at order 12 (5 is the most the budget
  takes there). Every plate kind is held to it: one part of any kind at any order (at most 15
  terms) is inside it, so only a compound can exceed it.

The scene language is not part of the input hash (scene/inputs.py): a budget changes no generated model.
"""
from __future__ import annotations

from .checks import SceneError

MAX_DEPTH = 8             # compounds inside compounds
MAX_TERMS = 16 * (2 + 3)  # = MAX_PARTS parts at field.order 2 (module docstring)
MAX_ORDER = 12            # the highest field order a scene takes (scene/load.py; derive/field_order.py)
TERMS_BEYOND_ORDER = 3    # Phi_0 ... Phi_{order+2}: order + 3 terms a part


def shape(table: dict) -> tuple[int, int]:
    """(leaf parts, nesting depth) of a plate table, without recursion: a plate of another kind is
    (1, 0), a compound of plates (n, 1), a compound inside it adds a level."""
    leaves, depth, todo = 0, 0, [(table, 0)]
    while todo:
        node, level = todo.pop()
        parts = node.get("parts") if isinstance(node, dict) and node.get("kind") == "compound" else None
        if not isinstance(parts, list):
            leaves += 1
            continue
        depth = max(depth, level + 1)
        if depth > MAX_DEPTH:           # deep enough to refuse: the rest need not be walked
            return leaves, depth
        todo.extend((p, level + 1) for p in parts)
    return leaves, depth


def check_nesting(table: dict, where: str) -> None:
    """Refuse a plate whose compounds nest more than MAX_DEPTH levels deep."""
    _, depth = shape(table)
    if depth > MAX_DEPTH:
        raise SceneError(f"[{where}] nests compounds more than {MAX_DEPTH} levels deep, the budget of nesting: "
                         "a compound's parts add up whatever their nesting, so list them in fewer levels")


def field_terms(table: dict, field: dict) -> tuple[int, int, int]:
    """(terms, parts, order): the field terms a plate derives (module docstring), its leaf parts and
    the field order counted (the scene's, or MAX_ORDER with field.tolerance)."""
    order = field.get("order")
    order = order if isinstance(order, int) and not isinstance(order, bool) else MAX_ORDER
    parts, _ = shape(table)
    return parts * (order + TERMS_BEYOND_ORDER), parts, order


def check_size(table: dict, field: dict) -> None:
    """Refuse a plate that would derive more than MAX_TERMS field terms, in one line with the count."""
    terms, parts, order = field_terms(table, field)
    if terms <= MAX_TERMS:
        return
    chosen = "field.order" if "order" in field else "the highest order field.tolerance may choose"
    fits = MAX_TERMS // (order + TERMS_BEYOND_ORDER)
    lower = max((n for n in range(2, order, 2) if parts * (n + TERMS_BEYOND_ORDER) <= MAX_TERMS), default=None)
    fix = (f"give at most {fits} parts at this order" + (f", or field.order = {lower}" if lower else ""))
    raise SceneError(f"the plate would derive {terms} field terms ({parts} parts x ({chosen} {order} + "
                     f"{TERMS_BEYOND_ORDER}): each part's Phi_0 ... Phi_{order + 2}), more than the derivation "
                     f"budget of {MAX_TERMS}: {fix}")
