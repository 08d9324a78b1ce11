"""Exact field of a rectangular block magnet (Furlani 2001) or thin rectangular layer (its rim
current, Biot-Savart); a centred hole takes away a cylinder (Derby & Olbert 2010) or a thin disk
(its rim loop) of the same magnetisation."""
from levitron.scene.plates.rectangle import block, holed

from levitron.runtime.physics.field.exact_field import (
    annulus_field,
    block_field,
    dipole_density,
    rect_loop_field,
    ring_magnet_field,
)


def field(table, p, points, part_field):
    if block(table):
        b = block_field(points, p["side_x"], p["side_y"], p["thickness"], p["magnetization"])
        if holed(table):
            b = b - ring_magnet_field(points, p["hole"], 0.0, p["thickness"], p["magnetization"])
        return b
    b = rect_loop_field(points, p["side_x"], p["side_y"], dipole_density(p["rho"]))
    if holed(table):
        b = b - annulus_field(points, p["hole"], 0.0, dipole_density(p["rho"]))
    return b
