"""Exact field of a rectangular block magnet (Furlani 2001) or thin rectangular layer (its rim
current, Biot-Savart)."""
from levitron.derive.plates.rectangle import block

from levitron.runtime.physics.exact_field import block_field, dipole_density, rect_loop_field


def field(table, p, points, part_field):
    if block(table):
        return block_field(points, p["side_x"], p["side_y"], p["thickness"], p["magnetization"])
    return rect_loop_field(points, p["side_x"], p["side_y"], dipole_density(p["rho"]))
