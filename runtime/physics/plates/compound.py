"""Exact field of a compound plate: the sum of its parts', each times its sign where it has one
(None if a part has no closed form)."""
import numpy as np

from levitron.scene.plates.compound import SIGN


def field(table, p, points, part_field):
    total = np.zeros((len(points), 3))
    for i, part in enumerate(table["parts"]):
        b = part_field(part, p.part(i), points)
        if b is None:
            return None
        total += p.part(i)[SIGN] * b if SIGN in part else b
    return total
