"""Many runs on the chunked C driver: stability maps (serial, local processes, dask), the launch
Monte Carlo and batched simulations.

Public surface: Scan (the map's answer; ScanResult its old name), monte_carlo, scan, simulate_many,
wilson. Names load lazily (PEP 562), so importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "Scan": "scan_answer",
    "ScanResult": "scan_answer",
    "monte_carlo": "launch_odds",
    "scan": "stability_map",
    "simulate_many": "batch",
    "wilson": "launch_odds",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
