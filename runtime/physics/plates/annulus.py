"""Exact field of the thin annulus (thesis eq. 2.2.11): two current loops (runtime/physics/field/exact_field.py)."""
from levitron.runtime.physics.field.exact_field import annulus_field, dipole_density


def field(table, p, points, part_field):
    return annulus_field(points, p["a"], p["w"], dipole_density(p["rho"]))
