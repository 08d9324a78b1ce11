"""`Study`: one scene with its model, and every question the toolchain answers about it."""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import numpy.typing as npt

from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.stability import differentiable as diffable
from levitron.runtime.model.scenes import load_scene
from levitron.runtime.design.constraints import Constraint
from levitron.runtime.design.optimize import optimize as _optimize
from levitron.runtime.errors import UserError
from levitron.runtime.design.measurements import Row, read_rows
from levitron.runtime.design.fit import fit as _fit
from levitron.runtime.model.load import NEEDS_OF_PART, Model, load_model
from levitron.runtime.design.scene_keys import Vary, key_value, pvector, with_values
from levitron.runtime.ui.human import Units

from . import arguments as arg
from .results import (Design, Equilibria, Fit, HeightFit, LaunchDesign, LaunchOdds, Scan, Simulation, Simulations,
                      Stability, Trim, YieldDesign)
from .study_options import (MANY_OPTIONS, SIMULATE_ALIASES, SIMULATE_OPTIONS, Quantity, checked_calls, given,
                            override_texts)
from .study_options import in_scene_units as _in_scene_units
_Designs = Design | LaunchDesign | YieldDesign       # what Study.optimize answers

if TYPE_CHECKING:
    from levitron.runtime.integrate.propagator import Propagator
    from levitron.runtime.physics.stability.modes import Modes
    from levitron.runtime.physics.stability.rotating_modes import TurningModes


def load(scene: str | Path, overrides: Mapping[str, float | str] | None = None, **unknown: object) -> Study:
    """A scene by name (scenes/) or path, with overrides by scene key, e.g. {"top.mass": 0.05}
    (numbers may be NumPy scalars); derives its model when needed. Errors: levitron.UserError
    (one line, as on the CLI; a misspelt argument too)."""
    for k in unknown:
        arg.choice(k, "load: argument", ["scene", "overrides"])
    if not isinstance(scene, (str, Path)):
        raise UserError(f"scene must be a scene name or a path to a .toml file, not {scene!r}")
    sets = override_texts(overrides)
    return Study(load_model(load_scene(scene, sets)))


class Study:
    """A scene and its generated model. `model` is runtime.model.load.Model (parameter vector p in the
    order model.param_names); users name numbers by scene keys (`value`, `p_of`)."""

    def __init__(self, model: Model):
        self.model, self.scene, self.overrides = model, model.scene, list(model.scene.overrides)
        self._cs: diffable.CasadiStability | None = None

    def __repr__(self) -> str:
        over = f", overrides={self.overrides}" if self.overrides else ""
        units = "SI" if self.units.si else "dimensionless"
        return (f"Study(scene={self.scene.name!r}{over}, {units}, parts={self.model.parts}, "
                f"{self.model.manifest.plate} plate)")

    @property
    def units(self) -> Units:
        """How this scene's numbers are shown (its `units` key, else decided by g): the results'
        repr and message use it, so a dimensionless scene's show no SI unit."""
        return Units.of_scene(self.scene)

    # ---- parameters by scene key
    def keys(self) -> list[str]:
        """The scene's numeric keys (`top.mass`, `plate.hole`, ...; units: docs/scenes.md)."""
        return arg.scene_keys(self.scene.data)

    def value(self, key: str) -> float:
        """The scene's number at `key` (its unit: docs/scenes.md); an unknown key lists them."""
        arg.choice(key, "scene key", self.keys())
        return key_value(self.scene.data, key)

    def p_of(self, values: Mapping[str, float] | None = None) -> npt.NDArray[np.float64]:
        """The parameter vector p with the given scene keys changed (re-resolved and validated)."""
        return pvector(self.model.param_names, with_values(self.scene, dict(values or {})))

    # ---- CasADi
    def functions(self) -> dict[str, Any]:
        """casadi.Functions: the generated ones ((in, p) -> out: onaxis, reduced_rhs, full_jac, ...)
        and the stability ones of runtime/physics/stability/differentiable.py with named inputs and outputs:
        z_s(z_guess, p) -> (z_s, stiffness), z_c(z_guess, p) -> (z_c, max_mass),
        spin(z_guess, sigma_lo_guess, sigma_hi_guess, p) -> (z_s, sigma_lo, sigma_hi),
        band(z_c_guess, z_hi_guess, s_guess, t_guess, p) -> (z_lo, z_hi, m_hi, m_lo, mass_window)."""
        def absent(name: str) -> str | None:
            part = name.split("_")[0]
            if "_" in name and part in NEEDS_OF_PART and part not in self.model.parts:
                return (f"function {name!r}: scene '{self.scene.name}' has no {part} model (model.needs = "
                        f"{self.scene.needs}): add \"{part}\" to model.needs in the scene")
            return None
        out = arg.Named("function", {name: self.model.casadi(name) for name in self.model.manifest.functions},
                        absent)
        out.update(self.casadi_stability.functions)
        return out

    @property
    def casadi_stability(self) -> diffable.CasadiStability:
        if self._cs is None:
            self._cs = diffable.CasadiStability(self.model)
        return self._cs

    def quantities(self) -> list[str]:
        """The names `gradient` takes: the outputs of the stability Functions."""
        return list(dict.fromkeys(n for F in self.casadi_stability.functions.values()
                                  for n in F.name_out()))

    def gradient(self, quantity: str, keys: Sequence[str]) -> dict[str, float]:
        """d quantity / d key for scene keys (quantity: z_s, stiffness, z_c, max_mass, sigma_lo,
        sigma_hi, z_lo, z_hi, m_lo, m_hi, mass_window; exact, through the rootfinders), at the
        scene's values. keys: a list of scene keys (one string is refused, not spelled out)."""
        from levitron.runtime.design.scene_keys import KeyMap
        arg.choice(quantity, "quantity", self.quantities())
        keys = arg.names(keys, "keys", self.keys(), each="scene key")
        x = np.array([self.value(k) for k in keys])
        if not np.all(x != 0):
            raise UserError(f"gradient: a key at 0 ({keys[int(np.argmin(np.abs(x)))]}) has no relative "
                            "neighbourhood: give the derivative at a nonzero value")
        km = KeyMap(self.scene, self.model.param_names,
                    [Vary(k, *sorted((v * 0.99, v * 1.01))) for k, v in zip(keys, x)])
        _, p = km.exact(x)
        J = self.casadi_stability.jacobian(quantity, p)
        if J is None:
            raise arg.UserError(f"{quantity} does not exist for this scene (no stable hover, "
                                "spin interval or band): see Study.stability() and .equilibria()")
        dpdx = p[:, None] * km.E / x[None, :]
        return dict(zip(keys, map(float, J @ dpdx)))

    # ---- physics
    @_in_scene_units
    def equilibria(self) -> Equilibria:
        """Vertical equilibria, z_c, the largest mass and the stable band (thesis 3.3.1-3.3.3):
        runtime/physics/equilibrium/answer.py's answer, the one `levitron equilibrium` prints."""
        return Equilibria.of(self.model)

    @_in_scene_units
    def stability(self, height: Quantity | None = None, *, level_tolerance: bool = False) -> Stability:
        """The spin interval at the hover height, by the exact route (thesis 3.3.9-3.3.16):
        runtime/physics/stability/answer.py's answer, the one `levitron stability` prints. height
        (m): instead the top that hovers there, of mass m(z) = -mu Phi_2(z)/g (`mass`). Over a
        tilted base (plate.tilt) by the eigenvalue route at the equilibrium off the axis
        (`equilibrium`: position, axis; stiffness None). level_tolerance: also how level the base
        and how well aligned the magnet must be (needs plate.tilt in the scene)."""
        h = None if height is None else arg.number(height, "height")
        return Stability.of(self.model, height=h, level_tolerance=bool(level_tolerance))

    @_in_scene_units
    def modes(self, spin: Quantity, height: Quantity | None = None) -> Modes | TurningModes:
        """The linear modes at `spin` (rad/s), those `levitron stability --spin` prints: name, frequency,
        sense and energy (Krein) sign of each (runtime/physics/stability/modes.py's Modes; height (m) as
        `stability` takes it). The resonances: `stability().resonances`. A tilted magnet: rotating_modes.py."""
        from levitron.runtime.physics.stability.rotating_modes import modes_at
        return modes_at(self.model, arg.number(spin, "spin"), None if height is None else arg.number(height, "height"))

    @_in_scene_units
    def simulate(self, spin: Quantity, *, tilt: Quantity | None = None, offset: Quantity | None = None,
                 t_end: Quantity | None = None, integrator: str | None = None, tol: Quantity | None = None,
                 box: Quantity | None = None, plot: str | Path | None = None, part: str | None = None,
                 h: Quantity | None = None, step: Quantity | None = None, n_out: int | None = None,
                 azimuth: Quantity | None = None, tilt_azimuth: Quantity | None = None,
                 save: str | Path | None = None) -> Simulation:
        """One trajectory (runtime.simulate.run.simulate), with the command line's options; each
        left at None takes the command's default.

        Args:
            spin: the spin rate (rad/s).
            tilt: the initial tilt of the axis (rad; default 0.005: a launch with tilt 0 and offset 0
                tests nothing and gives levitating None).
            offset: the initial horizontal offset (m).
            t_end: the run length (s; in air the run ends when the top falls: details["flight"]).
            integrator: a method of runtime/integrate/methods.py or "auto".
            tol: the integrator's tolerance.
            box: the half-width of the box the top must stay in (m; default z_s / 2).
            plot: a path to draw the run into (Simulation.plot).
            part: "full" or "reduced" (the model's part to run).
            h: the fixed step (s) of a fixed-step integrator; step: the same (the command's name).
            n_out: how many samples the answer keeps.
            azimuth: the direction of the tilt (rad); tilt_azimuth: the same (the command's name).
            save: a .csv, .npz or .parquet path to write the trajectory to (Simulation.save).
        """
        options: dict[str, Any] = given(tilt=tilt, offset=offset, t_end=t_end, integrator=integrator, tol=tol,
                                        box=box, plot=plot, part=part, h=h, step=step, n_out=n_out,
                                        azimuth=azimuth, tilt_azimuth=tilt_azimuth, save=save)
        from levitron.runtime.simulate import trajectory_file
        from levitron.runtime.simulate.run import simulate
        options = arg.options(options, SIMULATE_OPTIONS, SIMULATE_ALIASES, "simulate option",
                           ("tilt", "offset", "t_end", "tol", "box", "h", "azimuth"))
        plot, save = options.pop("plot", None), options.pop("save", None)
        if save is not None:
            trajectory_file.check_path(save)
        sim = simulate(self.model, arg.number(spin, "spin"), **options)
        if plot is not None:
            sim.plot(plot)
        if save is not None:
            sim.save(save, flag="«save»")
        return sim

    @_in_scene_units
    def simulate_many(self, spin: npt.ArrayLike, *, tilt: npt.ArrayLike | None = None,
                      offset: npt.ArrayLike | None = None, azimuth: npt.ArrayLike | None = None,
                      tilt_azimuth: npt.ArrayLike | None = None, t_end: Quantity | None = None,
                      integrator: str | None = None, tol: Quantity | None = None, box: Quantity | None = None,
                      h: Quantity | None = None, step: Quantity | None = None, part: str | None = None,
                      values: Mapping[str, npt.ArrayLike] | None = None) -> Simulations:
        """Many launches in one call (runtime/scan/batch.py: one call of the C chunk driver, the
        lane variant of the rhs where it verifies), each the run `simulate` makes with the same
        options, bit for bit: spin (rad/s), tilt (rad), offset (m), azimuth or tilt_azimuth (rad)
        are numbers or 1-D arrays, broadcast to one length; `values` {scene key: number or array}
        gives each launch its own parameters (re-resolved like p_of, each with its own hover
        height); t_end (s), integrator (a C one), tol, box (m), h or step (s), part: one for all,
        as simulate's. A launch whose top cannot hover (a mass too heavy for the plate) is one
        result among the others: status "no_hover_height", `reason` saying why, not run."""
        options: dict[str, Any] = given(tilt=tilt, offset=offset, azimuth=azimuth, tilt_azimuth=tilt_azimuth,
                                        t_end=t_end, integrator=integrator, tol=tol, box=box, h=h, step=step,
                                        part=part, values=values)
        from levitron.runtime.scan.batch import launch_columns, simulate_many
        options = arg.options(options, MANY_OPTIONS, SIMULATE_ALIASES, "simulate_many option",
                              ("t_end", "tol", "box", "h"))
        values = arg.launch_values(options.pop("values", None) or {}, {"spin": spin, **options})
        p = None
        cols: dict[str, Any] = {}
        if values:
            keys = list(values)
            for key in keys:
                arg.choice(key, "scene key", self.keys())
            # the lengths checked with the launch's own columns, so a mismatch names the scene key
            launch = {k: spin if k == "spin" else options[k] for k in ("spin", "tilt", "offset", "azimuth")
                      if k == "spin" or options.get(k) is not None}
            cols = launch_columns({**launch, **{k: values[k] for k in keys}})
            rows: dict[tuple[Any, ...], Any] = {}
            p = np.array([rows.setdefault(key, self.p_of(dict(zip(keys, key))))
                          for key in zip(*(cols[k].tolist() for k in keys))])
        out = simulate_many(self.model, spin, p=p, **options)
        inputs = dict(out["inputs"], **({k: cols[k] for k in values} if values else {}))
        return Simulations(out["levitating"], out["untested"], out["status"], out["t_survived"],
                           out["rhs_evals"], out["steps"], out["z_s"], out["final_state"],
                           out["states"], inputs, out["wall_s"],
                           {k: out[k] for k in ("t_end", "integrator", "integrator_requested", "tol",
                                                "step", "lanes")}, self.units,
                           np.array(out["reason"], dtype=object))

    @_in_scene_units
    def launch(self, n: int | None = None, seed: int | None = None,
               inputs: Mapping[str, object] | None = None, *, success_time: Quantity | None = None,
               t_end: Quantity | None = None, integrator: str | None = None, tol: Quantity | None = None,
               workers: int | None = None, scheduler: str | None = None) -> LaunchOdds:
        """Launch odds by Monte Carlo (runtime/scan/launch_odds.py): inputs maps spin, tilt, tilt_azimuth,
        offset, velocity, mass, strength, temperature to "normal:MEAN,SD", "uniform:LO,HI" or a
        number (default: the scene's [launch] table, else the scene-scaled defaults); n, seed and
        the options success_time (s), t_end (s) default to the table's too, as on the command line
        (else 1000 launches, seed 0); options also integrator, tol, workers, scheduler. The same
        seed gives the same verdicts serially, with processes and on dask. The result's `launches`
        holds every launch as arrays (its inputs as run, verdict, flight time). Each option left
        at None takes the command's default."""
        from levitron.runtime.scan.launch_odds import Request
        request = Request.of(self.scene.data.get("launch", {}), inputs, n=n, seed=seed, success_time=success_time,
                             t_end=t_end, integrator=integrator, tol=tol, workers=workers, scheduler=scheduler)
        return request.run(self.model, quiet=True)

    @_in_scene_units
    def trim(self, n: int | None = None, seed: int | None = None,
             inputs: Mapping[str, object] | None = None, *, success_time: Quantity | None = None,
             t_end: Quantity | None = None, integrator: str | None = None, tol: Quantity | None = None,
             workers: int | None = None, scheduler: str | None = None) -> Trim:
        """The mass to set so that most launches by hand float (runtime/design/trim.py): the
        launch-odds design over top.mass in the stable band, the launches taken as Study.launch
        takes them (n, seed, inputs, success_time, t_end, integrator, tol, workers, scheduler)."""
        from levitron.runtime.design.trim import trim
        from levitron.runtime.scan.launch_odds import Request
        request = Request.of(self.scene.data.get("launch", {}), inputs, n=n, seed=seed, success_time=success_time,
                             t_end=t_end, integrator=integrator, tol=tol, workers=workers, scheduler=scheduler)
        return trim(self.model, request)

    @_in_scene_units
    def propagator(self, part: str = "reduced", integrator: str = "auto", tol: Quantity = 1e-9,
                   spin: Quantity = 0.0, box: bool | Quantity = False) -> Propagator:
        """A run prepared once and repeated cheaply (runtime/integrate/propagator.py):
        ``prop(x0, t_end)`` is the state at t_end (s) of the run from x0 (the part's states in
        order, ``prop.states``), about 1 us of Python around the C integration; or in place,
        ``prop.state[:] = x0; prop.propagate(t_end)``. integrator: an adaptive C method (dop853,
        vern9, auto; taylor on the reduced model); tol relative to the scene's state magnitudes
        (lengths z_s, linear momenta m sqrt(g z_s), angles 1 rad, angular momenta
        max(C |spin|, A sqrt(g / z_s)), with spin in rad/s). box: False (none: a run goes to t_end),
        True (simulate's: |z - z_s| and the radial offset within z_s / 2) or a half-width (m); a run
        that leaves it stops there, ``prop.status`` "left_box" at ``prop.t_final``."""
        from levitron.runtime.integrate.propagator import Propagator
        from levitron.runtime.simulate.start import default_box, state_scales
        arg.choice(part, "part", tuple(NEEDS_OF_PART))     # a part this scene lacks: Model.part says so
        pt = self.model.part(part)
        z_s = eqm.hover_height(self.model, self.model.p)
        scale = state_scales(pt, z_s, arg.number(spin, "spin"), self.model.pvals())
        half = bool(box) if isinstance(box, (bool, np.bool_)) else arg.number(box, "box")
        bx = None if half is False else default_box(pt, z_s, None if half is True else half)
        return Propagator(pt, integrator, arg.number(tol, "tol"), scale=scale, box=bx)

    @_in_scene_units
    def scan(self, spins: npt.ArrayLike, axis: str, values: npt.ArrayLike, *, t_end: Quantity | None = None,
             integrator: str | None = None, tol: Quantity | None = None, workers: int | None = None,
             scheduler: str | None = None, base_tilt: Quantity | None = None, h: Quantity | None = None,
             quiet: bool | None = None, engine: str | None = None,
             scheduler_timeout: Quantity | None = None) -> Scan:
        """A stability map: runtime/scan/scan_answer.py's Scan (the answer `levitron scan` prints;
        its actions plot(path) and save(path)) over spins (rad/s) and one second axis:

        * "tilt": the initial tilt of the axis (rad);
        * "mass": the top's mass (kg), each started at its own hover height;
        * "height": the initial vertical displacement as a FRACTION of the hover height,
          z0 = z_s (1 + h), with -0.5 < h < 0.5 (not metres: 0.046 means z0 = 1.046 z_s;
          scenes may be dimensionless); values outside are refused.

        options (None: the command's default): t_end (s), integrator, tol, workers, scheduler,
        base_tilt (rad), h (s), quiet, engine, scheduler_timeout (s) (runtime.scan.stability_map.scan)."""
        from levitron.runtime.scan.stability_map import scan
        from levitron.runtime.scan.grid import AXES, check_axis
        arg.choice(axis, "scan axis", AXES)
        options: dict[str, Any] = given(t_end=t_end, integrator=integrator, tol=tol, workers=workers,
                                        scheduler=scheduler, base_tilt=base_tilt, h=h, quiet=quiet, engine=engine,
                                        scheduler_timeout=scheduler_timeout)
        grid, others = self._grid(spins, "spins"), self._grid(values, axis)
        check_axis(axis, np.sort(others))
        return scan(self.model, grid, axis, others, **options)

    @staticmethod
    def _grid(values: object, what: str) -> npt.NDArray[np.float64]:
        """A 1-D array of finite numbers (a list, a tuple, a NumPy array; one number is a grid of one)."""
        if isinstance(values, str):
            raise arg.UserError(f"{what} must be numbers (a list or an array), not the string {values!r}")
        try:
            a = np.atleast_1d(np.asarray(arg.real_column(values, what), float))
        except (TypeError, ValueError):
            raise arg.UserError(f"{what} must be numbers (a list or an array), not {values!r}") from None
        if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)):
            raise arg.UserError(f"{what} must be a non-empty 1-D list of finite numbers")
        return a

    # ---- design and fitting
    @_in_scene_units
    def optimize(self, maximize: str, vary: Mapping[str, tuple[float, float]],
                 constrain: Sequence[str] = (), grid: int = 20, *, n: int | None = None,
                 seed: int | None = None, inputs: Mapping[str, object] | None = None,
                 tolerance: Mapping[str, float] | None = None, success_time: Quantity | None = None,
                 t_end: Quantity | None = None, integrator: str | None = None, tol: Quantity | None = None,
                 workers: int | None = None, scheduler: str | None = None, kit: Mapping[str, str] | None = None,
                 washers: Sequence[float] | None = None, kits: int | None = None) -> _Designs:
        """Maximise spin-range, spin-ratio or mass-window over scene keys in boxes {key: (lo, hi)},
        with constraints such as "stiffness>=1" (runtime/design/optimize.py; IPOPT, verified): a
        Design. Or maximise "launch-odds", the odds that a launch by hand floats
        (runtime/design/launch_design.py): a LaunchDesign; or "yield", the kits of a production run
        (kit {"strength"|"mass"|a scene key: its spread}, washers (kg), kits, over the scene's [production])
        that float after their owners trim them (runtime/design/yield_design.py): a YieldDesign. Both take
        their launches as Study.launch does (n, seed, inputs, success_time, t_end, integrator, tol, workers,
        scheduler; None: the command's default) and no constraint. Each says how sharp it is (`sharpness`)."""
        launch_options = given(success_time=success_time, t_end=t_end, integrator=integrator, tol=tol,
                               workers=workers, scheduler=scheduler)
        names = arg.names(constrain, "constrain")
        varies = arg.varies(vary)
        tols = cast("dict[str, float] | None", tolerance)
        if maximize in ("launch-odds", "yield"):
            from levitron.runtime.design.launch_design import maximize_launch_odds
            from levitron.runtime.scan.launch_odds import Request
            if names:
                raise UserError(f"maximize={maximize!r} takes no constrain: a top that cannot hover or falls "
                                "already counts as a failure")
            request = Request.of(self.scene.data.get("launch", {}), inputs, n=n, seed=seed, **launch_options)
            if maximize == "yield":
                from levitron.runtime.design.production import Production
                from levitron.runtime.design.yield_design import maximize_yield
                prod = Production.of(kit, washers, kits, request.seed, self.scene.data.get("production"))
                return maximize_yield(self.model, varies, request, prod, tolerance=tols)
            from levitron.runtime.design.design_notes import with_launch_notes
            return with_launch_notes(self.model, maximize_launch_odds(self.model, varies, request, tolerance=tols))
        passed = [k for k, v in (("n", n), ("seed", seed), ("inputs", inputs), ("kit", kit), ("washers", washers),
                                 ("kits", kits)) if v is not None]
        if passed or launch_options:
            raise UserError(f"{', '.join([*passed, *launch_options])}: launch options go with "
                            "maximize='launch-odds' or 'yield' only")
        return _optimize(self.model, varies, maximize, [Constraint.parse(c) for c in names], grid, tols)

    @_in_scene_units
    def fit_height(self, z_star: float, param: str = "mu") -> HeightFit:
        """The value of one parameter (a scene key such as plate.murho or top.mass, or a generated
        parameter's name, default mu) at which the top hovers at z_star (m): m g + mu Phi_2(z*) = 0
        (thesis eq. 3.3.2; runtime/design/fit_height.py, the answer `optimize --fit-height` prints)."""
        from levitron.runtime.design.fit_height import fit_equilibrium_height
        from levitron.runtime.physics.apparatus.level_only import refuse_tilted
        refuse_tilted(self.model, "fit_height")
        return fit_equilibrium_height(self.model, arg.number(z_star, "z_star"), param)

    @_in_scene_units
    def fit(self, data: str | Path | Sequence[Row], vary: Mapping[str, tuple[float, float]]) -> Fit:
        """Least squares of scene keys to measurements (a CSV path or runtime.design.measurements.Row list)."""
        rows = read_rows(data) if isinstance(data, (str, Path)) else data
        return _fit(self.model, rows, arg.varies(vary))


checked_calls(Study)
