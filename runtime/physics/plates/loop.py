"""Exact field of a circular current loop (complete elliptic integrals, runtime/physics/field/exact_field.py)."""
from levitron.runtime.physics.field.exact_field import loop_field


def field(table, p, points, part_field):
    return loop_field(points, p["a"], p["current"])
