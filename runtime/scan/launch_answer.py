"""The answer to "how often does a launch by hand float?": `LaunchOdds`, one type for every face
(`launch --json` is its `as_json()`, `Study.launch` returns it, the report, the launch-odds design
and the trim read it; docs/contract.md `launch`). runtime/scan/launch_odds.py's `monte_carlo`
computes it. Saving the launches and drawing their flight times are actions on it: `save(path)`,
`plot(path=None, ax=None)` (runtime/scan/launch_plot.py).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from levitron.runtime.simulate.simulation import NORMAL_ENDS
from levitron.runtime.ui.human import Units, quantity, sig

_SI = Units(si=True)


@dataclass(frozen=True, repr=False)
class LaunchOdds:
    """Launch odds by Monte Carlo (runtime/scan/launch_odds.py, docs/contract.md `launch`): probability of
    floating at least success_time (s), its 95 % Wilson interval, flight-time median and quartiles
    (s), the inputs ranked by their effect on the success rate; details: every key of the JSON;
    launches: every launch as data, {column: array of length n} (launch_summary.LAUNCH_UNITS: the
    inputs as run, mass in kg and mu absolute, strength the factor 1 + d, z_s, verdict, floats,
    flight_time), the table `levitron launch --save` writes; `save(path)` writes it too."""

    probability: float
    probability_ci95: tuple[float, float]
    n: int
    success_time: float
    flight_time: dict
    ranking: list
    details: dict = field(repr=False, default_factory=dict)
    units: Units = field(default=_SI, repr=False, compare=False)   # how repr and message show numbers
    launches: dict = field(repr=False, default_factory=dict, compare=False)
    scene: str = ""

    @classmethod
    def of(cls, out: dict, model) -> LaunchOdds:
        """The answer from monte_carlo's keys (launch_odds.summarize), its `launches` table apart."""
        details = {k: v for k, v in out.items() if k != "launches"}
        return cls(out["probability"], tuple(out["probability_ci95"]), out["n"], out["success_time"],
                   {k: out["flight_time"][k] for k in ("median", "q1", "q3")},
                   [(e["input"], e["effect"]) for e in out["ranking"]], details,
                   Units.of_scene(model.scene), out.get("launches", {}), model.scene.name)

    def as_json(self) -> dict:
        """docs/contract.md's `launch --json` (SI) but for the command's own `saved` and `out`."""
        return {**self.details, "scene": self.scene}

    def __getitem__(self, key: str):
        """A key of the JSON answer, as `launch --json` names it."""
        return self.details[key]

    def __contains__(self, key: str) -> bool:
        return key in self.details

    def get(self, key: str, default=None):
        return self.details.get(key, default)

    # ---- actions
    def save(self, path, flag: str = "save") -> str:
        """Write the launches to a .csv, .npz or .parquet file (runtime/simulate/trajectory_file.py)."""
        from levitron.runtime.simulate import trajectory_file
        return str(trajectory_file.write_columns(path, self.launches, flag=flag))

    def plot(self, path=None, ax=None):
        """Draw the flight times (runtime/scan/launch_plot.py): the censored runs as a bar of their
        own, the success time drawn in; into `ax` (an Axes) or a figure of its own, written to
        `path` (.png, .pdf, .svg) only when given one. Returns the matplotlib Figure (the Axes when
        given `ax`)."""
        from levitron.runtime.scan.launch_plot import histogram
        return histogram(self.details, path, self.units, self.scene, ax=ax)

    # a sample's verdict: its run ended normally, or it cannot hover (a launch that fails, no solver's)
    VERDICTS = NORMAL_ENDS + ("cannot_hover",)

    def _failed(self) -> dict:
        return {k: v for k, v in self.details.get("outcomes", {}).items() if k not in self.VERDICTS}

    @property
    def success(self) -> bool:
        """Every sample has its verdict: its run ended normally (reached t_end, or the top left the
        box), or its top cannot hover; not a solver failure or a step budget."""
        return not self._failed()

    @property
    def reason(self) -> str | None:
        """Why no launch was run, where the scene's top cannot hover (the odds are then 0)."""
        return self.details.get("reason")

    @property
    def message(self) -> str:
        if self.reason:
            return f"0% of {self.n} launches float: no launch can, {self.reason}"
        lo, hi = self.probability_ci95
        decided = self.n - self.details.get("no_verdict", 0)     # the odds leave out the runs with no verdict
        text = (f"{sig(100 * self.probability, 3)}% of {decided} launches float at least "
                f"{quantity(self.units, self.success_time, 's', '.4g')} (95% Wilson interval "
                f"{sig(100 * lo, 3)}-{sig(100 * hi, 3)}%)")
        failed = self._failed()
        if failed:
            text += (f"; {sum(failed.values())} runs did not end normally "
                     f"({', '.join(f'{k} {v}' for k, v in sorted(failed.items()))})")
        return text

    def __repr__(self) -> str:
        lo, hi = self.probability_ci95
        ft = self.flight_time
        top = f", most: {self.ranking[0][0]}" if self.ranking else ""
        u = self.units
        return (f"LaunchOdds(probability={self.probability:.3g} [{lo:.3g}, {hi:.3g}], n={self.n}, "
                f"success_time={quantity(u, self.success_time, 's', '.4g')}, flight_time median "
                f"{quantity(u, ft['median'], 's', '.4g')} (quartiles {ft['q1']:.4g}-"
                f"{quantity(u, ft['q3'], 's', '.4g')})"
                f"{top}, success={self.success})")
