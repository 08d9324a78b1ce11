"""A compound plate: the sum of its parts' on-axis potentials."""
from __future__ import annotations

from collections.abc import Callable

import sympy as sp

from .plate import Plate


def build(table: dict, prefix: str = "", *, build_part: Callable[[dict, str], Plate]) -> Plate:
    """Phi_k adds up over the parts (part i's symbols plate_<prefix>p<i>_<name>); the registry
    allows no part without axial symmetry (derive/plates/rectangle.py: can_be_part = False)."""
    parts = [build_part(p, f"{prefix}p{i}_") for i, p in enumerate(table["parts"])]
    symbols = tuple(s for p in parts for s in p.symbols)

    def phis(k: int) -> sp.Expr:
        return sp.Add(*[p.phi(k) for p in parts])

    return Plate("compound", phis(0), symbols, phis)
