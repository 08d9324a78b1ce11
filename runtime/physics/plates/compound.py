"""Exact field of a compound plate: the sum of its parts' (None if a part has none)."""
import numpy as np


def field(table, p, points, part_field):
    total = np.zeros((len(points), 3))
    for i, part in enumerate(table["parts"]):
        b = part_field(part, p.part(i), points)
        if b is None:
            return None
        total += b
    return total
