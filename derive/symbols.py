"""The symbols that every derive module shares: positions, physical parameters, Phi_k(z).

One place for names, so that the mechanics, the field and the emitters agree on them.
"""
from __future__ import annotations

import sympy as sp

X, Y, Z = sp.symbols("x y z", real=True)

# Physical parameters, in the order they open the parameter vector (plate parameters follow).
m, g, A, C, mu = sp.symbols("m g A C mu", real=True)
PHYSICAL = (m, g, A, C, mu)

# The base's tilt (scene keys plate.tilt, plate.tilt_azimuth; derive/mechanics.py): they close the
# parameter vector of a scene that declares them (after the plate's and the friction's).
base_tilt, base_tilt_azimuth = sp.symbols("base_tilt base_tilt_azimuth", real=True)
TILT = (base_tilt, base_tilt_azimuth)
# The magnet's centre along the axis from the centre of mass (scene key top.moment_offset; the
# moment sits at r + d n, derive/mechanics.py): after the tilt's in the parameter vector.
moment_offset = sp.Symbol("moment_offset", real=True)
# The angle between the magnetic moment and the symmetry axis (scene key top.moment_tilt; the moment
# mu (cos b n + sin b e1), e1 = R_bs e_x fixed in the body, derive/mechanics.py): last of all.
moment_tilt = sp.Symbol("moment_tilt", real=True)


class Phi(sp.Function):
    """Phi(k, z) = d^k Phi0 / dz^k, the k-th derivative of the on-axis potential (thesis eq. 2.2.6).

    Kept abstract through the mechanics so that one derivation serves every axisymmetric plate;
    d/dz Phi(k, z) = Phi(k + 1, z). The emitters replace Phi(k, z) by the plate's expressions.
    """

    nargs = 2
    is_real = True

    def fdiff(self, argindex=2):
        if argindex != 2:
            raise sp.ArgumentIndexError(self, argindex)
        k, z = self.args
        return Phi(k + 1, z)


def phi_orders(expr: sp.Basic) -> set[int]:
    """The orders k of every Phi(k, z) in expr."""
    return {int(f.args[0]) for f in expr.atoms(Phi)}


# A plate without axial symmetry enters the mechanics through an abstract field B_i(x, y, z); the
# emitters replace B_i and its derivatives by the plate's closed forms (derive/emit/lower.py).
B_FUNCS = tuple(sp.Function(f"B_{c}", real=True) for c in "xyz")


def abstract_field(x=X, y=Y, z=Z) -> sp.Matrix:
    return sp.Matrix([f(x, y, z) for f in B_FUNCS])
