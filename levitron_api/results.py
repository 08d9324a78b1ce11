"""Typed results of the public API (SI units, thesis 3.3). The design and fit results are
runtime.design.DesignResult and runtime.fit.FitResult; the scan result runtime.scan.ScanResult."""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Equilibrium:
    """One vertical equilibrium (thesis 3.3.2): z (m), vertically_stable (mu Phi_3 > 0, 3.3.3),
    stiffness U'' = mu Phi_3 (N/m), marginal (a double root at z_c)."""

    z: float
    vertically_stable: bool
    stiffness: float
    marginal: bool


@dataclass(frozen=True)
class Equilibria:
    """The equilibria of the top (thesis 3.3.1-3.3.3): equilibria; z_c (m, zero of Phi_3) and
    max_mass (kg, m(z_c)), None if the field holds no top; stable_band: heights (m) and masses (kg)
    where some spin stabilises a top hovering there (docs/contract.md), None if there is none."""

    equilibria: list[Equilibrium]
    z_c: float | None
    max_mass: float | None
    stable_band_z: tuple[float, float] | None
    stable_band_mass: tuple[float, float] | None


@dataclass(frozen=True)
class Stability:
    """Linear stability at the hover height (thesis 3.3): z_s (m); stiffness mu Phi_3(z_s) (N/m);
    spin_interval (rad/s) by the exact route, None if no spin stabilises (reason says why);
    routes_agree: the eigenvalue route confirms it (None without a full model)."""

    z_s: float | None
    stiffness: float | None
    spin_interval: tuple[float, float] | None
    reason: str | None
    routes_agree: bool | None


@dataclass(frozen=True)
class Simulation:
    """One trajectory from the hover height (docs/contract.md `simulate`): levitating (None for a
    launch on the invariant set, which tests nothing: details["untested"] says why); t_survived
    (s); max_excursion (m); energy_drift (relative; in air the energy balance's residual);
    rhs_evals; wall_s (s); final_state (the model's states, SI); details: every key of the
    command's JSON (in air also "flight": flight time, fall spin, the adiabatic t_cross)."""

    levitating: bool | None
    t_survived: float
    max_excursion: float
    energy_drift: float
    rhs_evals: int
    wall_s: float
    final_state: dict
    details: dict = field(repr=False, default_factory=dict)


@dataclass(frozen=True)
class LaunchOdds:
    """Launch odds by Monte Carlo (runtime/launch.py, docs/contract.md `launch`): probability of
    floating at least success_time (s), its 95 % Wilson interval, flight-time median and quartiles
    (s), the inputs ranked by their effect on the success rate; details: every key of the JSON."""

    probability: float
    probability_ci95: tuple[float, float]
    n: int
    success_time: float
    flight_time: dict
    ranking: list
    details: dict = field(repr=False, default_factory=dict)
