"""Compatibility names for callers not yet moved to the split modules (issue 8).

The linear stability analysis (thesis 3.3) lives in one module per idea:
  runtime/ray_algebra.py   exact polynomial / discriminant algebra (thesis 3.3.9-3.3.16)
  runtime/eigen_route.py   the Jacobian's eigenvalues on the imaginary axis (thesis 3.3.4-3.3.5)
  runtime/stability.py     both routes at the stable height: analyse, StabilityResult, stability_of
  runtime/equilibrium.py   the one equilibrium finder and model_onaxis
Remaining importers of this module: runtime/scan.py, tests/test_scan.py, tests/test_geometry.py;
delete it once they import from the modules above.
"""
from .eigen_route import full_equilibrium_state, transverse_matrix  # noqa: F401
from .equilibrium import model_onaxis  # noqa: F401
from .stability import analyse, model_callables  # noqa: F401
