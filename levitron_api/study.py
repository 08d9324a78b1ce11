"""`Study`: one scene with its model, and every question the toolchain answers about it."""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from derive.scene import SceneError, override_text
from runtime import equilibrium as eqm
from runtime import stability_casadi as sc
from runtime.commands.common import load as load_scene
from runtime.constraints import Constraint
from runtime.design import DesignResult
from runtime.design import optimize as _optimize
from runtime.errors import UserError
from runtime.fit import FitResult, Row, read_rows
from runtime.fit import fit as _fit
from runtime.model import Model, load_model
from runtime.scene_keys import Vary, key_value, pvector, with_values
from runtime.stability import stability_of

from .results import Equilibria, Equilibrium, Simulation, Stability


def override_texts(overrides: Mapping[str, object] | None) -> list[str]:
    """The --set texts of {scene key: value}, written by a TOML writer (derive.scene.override_text):
    a quote or a newline in a value stays inside it, and the command line's reader reads them."""
    if overrides is None:
        return []
    if not isinstance(overrides, Mapping):
        raise UserError(f"overrides must be a mapping of scene key -> value, e.g. {{'top.mass': 0.05}}; "
                        f"got {type(overrides).__name__}")
    try:
        return [override_text(k, v) for k, v in overrides.items()]
    except SceneError as exc:
        raise UserError(str(exc)) from None


def load(scene: str | Path, overrides: Mapping[str, float | str] | None = None) -> Study:
    """A scene by name (scenes/) or path, with overrides by scene key, e.g. {"top.mass": 0.05};
    derives its model when needed. Errors: levitron_api.UserError (one line, as on the CLI)."""
    if not isinstance(scene, (str, Path)):
        raise UserError(f"scene must be a scene name or a path to a .toml file, not {scene!r}")
    sets = override_texts(overrides)
    return Study(load_model(load_scene(scene, sets), sets), sets)


class Study:
    """A scene and its generated model. `model` is runtime.model.Model (parameter vector p in the
    order model.param_names); users name numbers by scene keys (`value`, `p_of`)."""

    def __init__(self, model: Model, overrides: Sequence[str] = ()):
        self.model, self.scene, self.overrides = model, model.scene, list(overrides)
        self._cs = None

    # ---- parameters by scene key
    def value(self, key: str) -> float:
        """The scene's number at `key` (its unit: docs/scenes.md)."""
        return key_value(self.scene.data, key)

    def p_of(self, values: Mapping[str, float] | None = None) -> np.ndarray:
        """The parameter vector p with the given scene keys changed (re-resolved and validated)."""
        return pvector(self.model.param_names, with_values(self.scene, dict(values or {})))

    # ---- CasADi
    def functions(self) -> dict:
        """casadi.Functions: the generated ones ((in, p) -> out: onaxis, reduced_rhs, full_jac, ...)
        and the stability ones of runtime/stability_casadi.py with named inputs and outputs:
        z_s(z_guess, p) -> (z_s, stiffness), z_c(z_guess, p) -> (z_c, max_mass),
        spin(z_guess, sigma_lo_guess, sigma_hi_guess, p) -> (z_s, sigma_lo, sigma_hi),
        band(z_c_guess, z_hi_guess, s_guess, t_guess, p) -> (z_lo, z_hi, m_hi, m_lo, mass_window)."""
        out = {name: self.model.casadi(name) for name in self.model.manifest.functions}
        out.update(self.casadi_stability.functions)
        return out

    @property
    def casadi_stability(self) -> sc.CasadiStability:
        if self._cs is None:
            self._cs = sc.CasadiStability(self.model)
        return self._cs

    def gradient(self, quantity: str, keys: Sequence[str]) -> dict[str, float]:
        """d quantity / d key for scene keys (quantity: z_s, stiffness, z_c, max_mass, sigma_lo,
        sigma_hi, z_lo, z_hi, m_lo, m_hi, mass_window; exact, through the rootfinders), at the
        scene's values."""
        from runtime.scene_keys import KeyMap
        if quantity not in self.casadi_stability.outputs():
            raise UserError(f"unknown quantity {quantity!r}: use one of "
                            f"{', '.join(self.casadi_stability.outputs())}")
        if isinstance(keys, str) or not keys:
            raise UserError("keys: give a non-empty list of scene keys, e.g. ['top.mass']")
        x = np.array([self.value(k) for k in keys])
        if not np.all(x != 0):
            raise UserError(f"gradient: a key at 0 ({keys[int(np.argmin(np.abs(x)))]}) has no relative "
                            "neighbourhood: give the derivative at a nonzero value")
        km = KeyMap(self.scene, self.model.param_names,
                    [Vary(k, *sorted((v * 0.99, v * 1.01))) for k, v in zip(keys, x)])
        _, p = km.exact(x)
        J = self.casadi_stability.jacobian(quantity, p)
        if J is None:
            raise UserError(f"{quantity} does not exist for this scene (no stable hover or spin "
                            "interval): check the scene")
        dpdx = p[:, None] * km.E / x[None, :]
        return dict(zip(keys, map(float, J @ dpdx)))

    # ---- physics
    def equilibria(self) -> Equilibria:
        """Vertical equilibria, z_c, the largest mass and the stable band (thesis 3.3.1-3.3.3)."""
        rep = eqm.equilibria_of(self.model, bands=True)
        band = rep.stable_band
        return Equilibria([Equilibrium(e.z, e.vertically_stable, e.stiffness, e.marginal)
                           for e in rep.equilibria], rep.z_c, rep.max_mass,
                          None if band is None else tuple(band.z),
                          None if band is None else tuple(band.mass))

    def stability(self) -> Stability:
        """The spin interval at the hover height, by the exact route (thesis 3.3.9-3.3.16)."""
        res = stability_of(self.model)
        k = None
        if res.z_s is not None:
            P = self.model.pvals()
            k = P["mu"] * float(self.model.onaxis(res.z_s)[3])
        return Stability(res.z_s, k, None if res.spin_interval is None else tuple(res.spin_interval),
                         res.reason, res.routes_agree)

    def simulate(self, spin: float, **options) -> Simulation:
        """One trajectory (runtime.simulate.simulate; options: tilt (rad), offset (m), t_end (s),
        integrator, tol, box (m), plot (path))."""
        from runtime.simulate import simulate
        out = simulate(self.model, spin, **options)
        return Simulation(bool(out["levitating"]), float(out["t_survived"]),
                          float(out["max_excursion"]), float(out["energy_drift"]),
                          int(out["rhs_evals"]), float(out["wall_s"]), dict(out["final_state"]),
                          out)

    def scan(self, spins: Sequence[float], axis: str, values: Sequence[float], **options):
        """A stability map over spins (rad/s) and one of tilt (rad), mass (kg), height (m):
        runtime.scan.ScanResult (options: t_end, integrator, tol, workers, ...)."""
        from runtime.scan import scan
        ref = str(self.scene.path) if self.scene.path else self.scene.name
        return scan(self.model, ref, self.overrides, np.asarray(spins, float), axis,
                    np.asarray(values, float), **options)

    # ---- design and fitting
    def optimize(self, maximize: str, vary: Mapping[str, tuple[float, float]],
                 constrain: Sequence[str] = (), grid: int = 20) -> DesignResult:
        """Maximise spin-range or spin-ratio over scene keys in boxes {key: (lo, hi)}, with
        constraints such as "stiffness>=1" (runtime/design.py; IPOPT, verified)."""
        return _optimize(self.model, _varies(vary),
                         maximize, [Constraint.parse(c) for c in constrain], grid)

    def fit(self, data: str | Path | Sequence[Row], vary: Mapping[str, tuple[float, float]]) -> FitResult:
        """Least squares of scene keys to measurements (a CSV path or runtime.fit.Row list)."""
        rows = read_rows(data) if isinstance(data, (str, Path)) else data
        return _fit(self.model, rows, _varies(vary))


def _varies(vary) -> list[Vary]:
    """{scene key: (lo, hi)} as Vary boxes, checked (the CLI's --vary KEY=LO:HI reads the same)."""
    if not isinstance(vary, Mapping) or not vary:
        raise UserError("vary: give a non-empty mapping of scene key -> (lo, hi), e.g. "
                        "{'top.mass': (0.05, 0.052)}")
    out = []
    for key, box in vary.items():
        if isinstance(box, (str, bytes)) or not hasattr(box, "__len__") or len(box) != 2:
            raise UserError(f"vary {key}: give a pair (lo, hi), not {box!r}")
        out.append(Vary.checked(key, box[0], box[1], f"vary {key!r}: {tuple(box)!r}"))
    return out
