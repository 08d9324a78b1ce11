"""Random states of the full model near a hover: the tests of a tilted base and a tilted moment
(tests/runtime/physics/apparatus/test_base_tilt.py, tests/derive/test_moment_tilt.py) evaluate the generated
functions there."""
from __future__ import annotations

import numpy as np

# the spread of each state of the full model (positions, angles, momenta: Tait-Bryan order)
SPREAD = np.array([0.01, 0.01, 0.01, 0.3, 0.3, 3, 1e-3, 1e-3, 1e-3, 1e-5, 1e-5, 1e-3])


def random_states(part, rng, n=20, height=0.1):
    """n states, each uniform within +-SPREAD of the origin, the height `height` above the plate."""
    for _ in range(n):
        x = rng.uniform(-1, 1, part.nx) * SPREAD
        x[part.states.index("z")] += height
        yield x
