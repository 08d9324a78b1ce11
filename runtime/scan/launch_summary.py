"""The statistics of the launches (runtime/scan/launch_odds.py runs them and its `summarize` makes
the answer): the 95 % Wilson interval of the odds, the inputs ranked by their effect on the success
rate, and every launch as data (`launches`, the table `launch --save` writes, its columns' units
and meanings).
"""
from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.scan.launch_inputs import APPARATUS
from levitron.runtime.scan.spreads import Dist

Z95 = 1.959963984540054          # the 97.5 % point of the standard normal
BINS = 5
RANGE95 = 3.86        # 95 % point of the range of BINS = 5 standard normals (Tippett's tables)


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion k / n (Wilson 1927)."""
    if n <= 0:
        raise UserError("the Wilson interval needs at least one sample")
    p = k / n
    den = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    # at k = 0 (k = n) the lower (upper) end is 0 (1) exactly, not the rounding of centre - half
    return (0.0 if k == 0 else max(0.0, centre - half)), (1.0 if k == n else min(1.0, centre + half))


def effects(S: Mapping[str, np.ndarray], ok: np.ndarray, dists: Mapping[str, Dist]) -> list[dict]:
    """Per input with a spread: the success rate in each of BINS quantile bins of the input, and
    its effect, the largest minus the smallest of those rates; ranked, largest effect first.
    `noise`: the effect an input without influence stays below by chance in 95 % of samples, the
    95 % point of the range of BINS normal rates, 3.9 binomial standard deviations of one bin's
    rate (3.9 sqrt(p (1 - p) / (n / BINS))), so that a small sample's ranking is read as it is."""
    out = []
    p = float(np.mean(ok)) if len(ok) else 0.0
    noise = RANGE95 * math.sqrt(p * (1 - p) / max(len(ok) / BINS, 1.0))
    for name, d in dists.items():
        if not d.spread:
            continue
        x = S[name]
        edges = np.quantile(x, np.linspace(0, 1, BINS + 1))
        idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, BINS - 1)
        rates = [float(ok[idx == b].mean()) if np.any(idx == b) else None for b in range(BINS)]
        have = [r for r in rates if r is not None]
        out.append({"input": name, "effect": (max(have) - min(have)) if have else 0.0, "noise": noise,
                    "bins": [[float(edges[b]), float(edges[b + 1])] for b in range(BINS)],
                    "success_rate": rates})
    return sorted(out, key=lambda e: -e["effect"])


# the columns of `launches` (launch --save, Study.launch().launches) and the SI unit of each ("1": a
# pure number; "text": the verdict): every input as the launch ran it, mass and strength absolute
# (the apparatus' columns only where the model has their terms)
LAUNCH_UNITS = {"launch": "1", "spin": "rad/s", "tilt": "rad", "tilt_azimuth": "rad", "offset": "m",
                "velocity": "m/s", "mass": "kg", "strength": "1", "temperature": "degC",
                **{a.name: a.unit for a in APPARATUS}, "mu": "A m^2",
                "z_s": "m", "verdict": "text", "floats": "1", "flight_time": "s"}
LAUNCH_MEANING = {
    "launch": "the launch's index (its place in the seed's draw)",
    "mass": "the top's mass as run, m (1 + d) (not the relative deviation d)",
    "strength": "the factor on the magnets' strength as sampled, 1 + d (1 = the scene's; temperature aside)",
    "mu": "the moment (times the plate's strength) the run used: the scene's mu x strength x the "
          "temperature's factor",
    "z_s": "the hover height of the launch's own top (NaN: it cannot hover)",
    "verdict": "how the run ended, as `outcomes` names it (completed: still up at t_end; left_box: fell; "
               "cannot_hover; ...)",
    "floats": "1 if the flight reached the success time, else 0",
    "base_tilt": "the base's tilt from level the launch ran over (rad; the model's base_tilt)",
    "base_tilt_azimuth": "the base's downhill direction (rad from +x towards +y)",
    "moment_tilt": "the angle of the magnet's moment from the top's axis in the launch (rad; moment_tilt)",
    "flight_time": "how long the top floated (t_end for a run still up)"}


def launches(S: Mapping[str, np.ndarray], pts: list[dict], ok: np.ndarray, t: np.ndarray) -> dict:
    """Every launch as data, one row each in the seed's order: the sampled inputs (spin, tilt,
    tilt_azimuth, offset, velocity, temperature and the apparatus' as drawn; mass and mu as the run used them,
    strength as the factor 1 + d), the launch's hover height, its verdict (the run's status), whether
    it floats, and its flight time (LAUNCH_UNITS)."""
    out = {"launch": np.arange(len(pts))}
    out.update({k: np.asarray(S[k], float) for k in S})
    out["mass"] = np.array([p["m"] for p in pts])
    out["strength"] = 1.0 + np.asarray(S["strength"], float)
    out["mu"] = np.array([p["mu"] for p in pts])
    out["z_s"] = np.array([p["z_s"] for p in pts])
    out["verdict"] = np.array([p["status"] for p in pts])
    out["floats"] = ok.astype(np.int64)
    out["flight_time"] = np.asarray(t, float)
    return {k: out[k] for k in LAUNCH_UNITS if k in out}


def cannot_hover(n: int, seed: int, reason: str, given, success_time, t_end) -> dict:
    """The answer (summarize's keys) where the scene's top has no hover height: every launch
    fails, none is run; `reason` says why (the optimiser scores such a design 0 the same way)."""
    return {"probability": 0.0, "probability_ci95": [0.0, 0.0], "successes": 0, "n": int(n), "no_verdict": 0,
            "seed": int(seed), "success_time": success_time, "t_end": t_end,
            "flight_time": {"median": 0.0, "q1": 0.0, "q3": 0.0, "censored": 0, "values": [0.0] * int(n)},
            "outcomes": {"cannot_hover": int(n)}, "ranking": [], "inputs": {k: str(v) for k, v in given.items()},
            "defaulted": [], "z_s": None, "spin_interval": None, "verdicts": [False] * int(n), "launches": {},
            "warnings": [], "reason": reason}
