"""A compound plate: the sum of its parts (each part's field times its sign, where it has one).

On the axis the Phi_k add up over the parts. Parts without axial symmetry (rectangles) bring their
exact 3-D field: the compound's field3d is their sum, and its `axial` the sum of the other parts'
Phi_k (and of the rectangles' own axial parts, their holes), which the full model expands to the
scene's order (Plate.model_field). Without such a part the compound is axisymmetric, as before.
"""
from __future__ import annotations

from collections.abc import Callable
from functools import reduce

import sympy as sp

from levitron.scene.plates.compound import SIGN

from .plate import Plate, plate_symbol


def _signed(sign: sp.Symbol | None, expr):
    return expr if sign is None else sign * expr


def _total(terms: list):
    """The sum of terms, the first one itself when it is alone (a compound of one part is that part)."""
    return reduce(lambda a, b: a + b, terms)


def build(table: dict, prefix: str = "", *, build_part: Callable[[dict, str], Plate]) -> Plate:
    """Part i's symbols are plate_<prefix>p<i>_<name>; a part with a `sign` key is multiplied by the
    parameter plate_<prefix>p<i>_sign (+1 or -1, scene/plates/compound.py)."""
    tables = table["parts"]
    parts = [build_part({k: v for k, v in p.items() if k != SIGN}, f"{prefix}p{i}_")
             for i, p in enumerate(tables)]
    signs = [plate_symbol(f"{prefix}p{i}_{SIGN}") if SIGN in p else None for i, p in enumerate(tables)]
    symbols = tuple(s for p, sign in zip(parts, signs) for s in p.symbols + ((sign,) if sign is not None else ()))

    def phis(k: int) -> sp.Expr:
        return sp.Add(*[_signed(sign, p.phi(k)) for p, sign in zip(parts, signs)])

    exact = [(p, sign) for p, sign in zip(parts, signs) if not p.axisymmetric]
    if not exact:
        return Plate("compound", phis(0), symbols, phis)
    expanded = ([(p.phi, sign) for p, sign in zip(parts, signs) if p.axisymmetric]
                + [(p.axial, sign) for p, sign in exact if p.axial is not None])

    def field3d(x, y, z) -> sp.Matrix:
        return _total([_signed(sign, sp.Matrix(p.field3d(x, y, z))) for p, sign in exact])

    potential3d = None
    if all(p.potential3d is not None for p, _ in exact):
        def potential3d(x, y, z) -> sp.Expr:
            return _total([_signed(sign, p.potential3d(x, y, z)) for p, sign in exact])

    def axial(k: int) -> sp.Expr:
        return sp.Add(*[_signed(sign, phi(k)) for phi, sign in expanded])

    return Plate("compound", phis(0), symbols, phis, field3d, potential3d, axial if expanded else None)
