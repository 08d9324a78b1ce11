"""Exact field of an axially magnetised ring / cylinder magnet (Derby & Olbert 2010)."""
from levitron.scene.plates.ring_magnet import hollow

from levitron.runtime.physics.field.exact_field import ring_magnet_field


def field(table, p, points, part_field):
    r_in = p["r_in"] if hollow(table) else 0.0
    return ring_magnet_field(points, p["r_out"], r_in, p["thickness"], p["magnetization"])
