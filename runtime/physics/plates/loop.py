"""Exact field of a circular current loop (complete elliptic integrals, runtime/physics/exact_field.py)."""
from levitron.runtime.physics.exact_field import loop_field


def field(table, p, points, part_field):
    return loop_field(points, p["a"], p["current"])
