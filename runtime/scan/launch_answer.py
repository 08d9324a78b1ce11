"""The answer to "how often does a launch by hand float?": `LaunchOdds`, one type for every face
(`launch --json` is its `as_json()`, `Study.launch` returns it, the report, the launch-odds design
and the trim read it; docs/contract.md `launch`). runtime/scan/launch_odds.py's `monte_carlo`
computes it. Saving the launches and drawing their flight times are actions on it: `save(path)`,
`plot(path=None, ax=None)` (runtime/scan/launch_plot.py). Its words are its own: `launch_lines`
(of its JSON) is the plain view `levitron launch` prints, its `lines(units)`, `message`, repr, a
notebook's table (`_repr_html_`) and the report's answer on the odds.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from levitron.runtime.simulate.simulation import NORMAL_ENDS
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plain_text import NOTHING_SAID, kept, said

_SI = Units(si=True)


def launch_input(name: str, spec: str, u: Units) -> str:
    """One input's distribution (the JSON's spec, SI) in the scene's units: "spin 1122 rad/s, sd
    112.2 rad/s (normal)", "tilt 0-0.02 rad (uniform)", "mass +0 %, sd 0.2 % (normal)" (a relative
    spread, rel:...), "temperature 20 degC"; a dimensionless scene's lengths and speeds bare."""
    from levitron.runtime.scan import launch_inputs as li
    from levitron.runtime.scan.spreads import parse_input
    si_unit = li.INPUT_UNITS[name]
    show = {"m": u.length, "1": lambda v: f"{sig(100 * v, 3)} %",
            "degC": lambda v: f"{sig(v)} degC"}.get(si_unit, lambda v: u.value(v, si_unit))
    d = parse_input(name, spec)
    if d.kind == "normal":
        mean = show(d.a) if si_unit != "1" else ("+" if d.a >= 0 else "") + show(d.a)
        return f"{name} {mean}, sd {show(d.b)} (normal)"
    if d.kind == "uniform":
        return f"{name} {show(d.a)} to {show(d.b)} (uniform)"
    return f"{name} {show(d.a)}"


def launches_line(r: dict, u: Units, scene=None, thermal: bool | None = None) -> str:
    """The launches the odds are of, in one line, the defaults marked as such (their settings as
    markers, worded per face). thermal: whether the scene's magnets have a temperature coefficient
    (None: read from `scene`)."""
    shown = [k for k in r["inputs"] if k != "temperature" or temperature_matters(r["inputs"][k], scene, thermal)]
    given = [launch_input(k, r["inputs"][k], u) for k in shown if k not in r.get("defaulted", ())]
    default = [launch_input(k, r["inputs"][k], u) for k in shown if k in r.get("defaulted", ())]
    return "launches: " + "; ".join(filter(None, (
        ", ".join(given),
        f"{', '.join(default)} (defaults: set them with «spin», «tilt», ... or a [launch] table)" if default else "")))


def thermal_of(scene) -> bool:
    """Whether the scene's magnets have a temperature coefficient."""
    data = getattr(scene, "data", None) or {}
    return any(float(data.get(t, {}).get("temperature_coefficient", 0.0)) != 0.0 for t in ("plate", "top"))


def temperature_matters(spec: str, scene, thermal: bool | None = None) -> bool:
    """Whether the launches' temperature says anything: it is spread, or the scene's magnets have a
    temperature coefficient (without one, and fixed, it changes nothing: not shown, which also
    keeps degC out of a dimensionless scene that does not model temperature)."""
    from levitron.runtime.scan import spreads
    if spreads.parse_dist("temperature", spec).spread or (scene is None and thermal is None):
        return True
    return thermal if thermal is not None else thermal_of(scene)


def launch_lines(r: dict, u: Units, scene=None, thermal: bool | None = None) -> list[str]:
    """The plain view of a launch's JSON, answer first: the odds with their interval; the flight
    times; what matters most; the launches; the files written (`saved`, `out` where given)."""
    if r.get("reason"):
        return [f"launch odds: 0% of {r['n']} launches float: the top cannot hover, so no launch was run",
                f"reason: {r['reason']}", u.note]
    lo, hi = r["probability_ci95"]
    ft = r["flight_time"]
    rank = [f"{e['input']} ({sig(100 * e['effect'], 3)} points of success rate across its quintiles"
            f"{'' if e['effect'] > e['noise'] else ', within the noise of this sample'})"
            for e in r["ranking"][:3]]
    outcomes = ", ".join(f"{k} {v}" for k, v in r["outcomes"].items())
    cens = f"; {ft['censored']} still up at the end of the run" if ft["censored"] else ""
    past = r.get("past_window") or {"launches": 0, "reason": None}
    stopped = r["no_verdict"] - past["launches"]
    at = lambda t: (">= " if t >= r["t_end"] * (1 - 1e-12) else "") + u.time(t)  # noqa: E731 (censored)
    return [
        f"launch odds: {sig(100 * r['probability'], 3)}% of {r['n'] - r['no_verdict']} launches float at least "
        f"{u.time(r['success_time'])} (95% Wilson interval {sig(100 * lo, 3)}-{sig(100 * hi, 3)}%)",
        f"{stopped} of {r['n']} runs stopped early without a verdict: not counted" if stopped else "",
        f"{past['launches']} of {r['n']} launches up at the end past their stable window, without a verdict: not "
        f"counted; {past['reason']}" if past["launches"] else "",
        *[f"warning: {w}" for w in r.get("warnings", [])],
        f"flight time: median {at(ft['median'])}, quartiles {at(ft['q1'])} - {at(ft['q3'])}"
        f" (runs of {u.time(r['t_end'])}{cens})",
        f"matters most: {'; '.join(rank)}" if rank else "no input has a spread",
        f"outcomes: {outcomes}",
        launches_line(r, u, scene, thermal),
        f"seed {r['seed']}, {r['integrator']} at tol {sig(r['tol'], 2)}",
        f"launches saved: {r['saved']['path']} ({r['saved']['rows']} rows: inputs, verdict, flight time)"
        if r.get("saved") else "",
        u.note,
        f"histogram: {r['out']}" if r.get("out") else ""]



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
    thermal: bool | None = field(default=None, repr=False, compare=False)   # magnets with a temperature coefficient
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, repr=False, compare=False)  # warnings as written

    @classmethod
    def of(cls, out: dict, model) -> LaunchOdds:
        """The answer from monte_carlo's keys (launch_odds.summarize), its `launches` table apart."""
        details = {k: v for k, v in out.items() if k != "launches"}
        return cls(out["probability"], tuple(out["probability_ci95"]), out["n"], out["success_time"],
                   {k: out["flight_time"][k] for k in ("median", "q1", "q3")},
                   [(e["input"], e["effect"]) for e in out["ranking"]], details,
                   Units.of_scene(model.scene), out.get("launches", {}), model.scene.name,
                   thermal_of(model.scene), said(warnings=out.get("warnings") or []))

    def as_json(self) -> dict:
        """docs/contract.md's `launch --json` (SI) but for the command's own `saved` and `out`; its
        numbers are the fields' (the keys the details carry)."""
        own = {"probability": self.probability, "probability_ci95": list(self.probability_ci95), "n": self.n,
               "success_time": self.success_time,
               "flight_time": {**self.details.get("flight_time", {}), **self.flight_time}}
        return {**self.details, **{k: v for k, v in own.items() if k in self.details}, "scene": self.scene}

    def __getitem__(self, key: str):
        """A key of the JSON answer, as `launch --json` names it."""
        return self.details[key]

    def __contains__(self, key: str) -> bool:
        return key in self.details

    def get(self, key: str, default=None):
        return self.details.get(key, default)

    # ---- actions
    def save(self, path, flag: str = "save") -> str:
        """Write the launches to a .csv, .npz or .parquet file (runtime/simulate/trajectory_file.py),
        with the columns' units (`column_units()`)."""
        from levitron.runtime.simulate import trajectory_file
        return str(trajectory_file.write_columns(path, self.launches, flag=flag, units=self.column_units()))

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

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (launch_lines of as_json: the one wording of every face), in `units`
        (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or self.units
        r = self.as_json()
        if "warnings" in self.said:     # as written (their quantities' markers), where the API worded them
            r["warnings"] = kept(r.get("warnings"), self.said["warnings"], self.units)
        return worded(launch_lines(r, u, thermal=self.thermal), u, face)

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    def __repr__(self) -> str:
        return text_repr("LaunchOdds", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Launch odds", self.lines(), None if self.reason else self.plot())

    # ---- as tables (runtime/ui/frames.py)
    def column_units(self) -> dict[str, str]:
        """{column of `launches`: unit} (launch_summary.LAUNCH_UNITS: SI, "1" a pure number, "text"
        the verdict; the scene's units in a dimensionless scene), as `launch --save` names them."""
        from levitron.runtime.scan.launch_summary import LAUNCH_UNITS
        from levitron.runtime.ui import frames
        return frames.shown_units({k: LAUNCH_UNITS.get(k, "") for k in self.launches}, self.units)

    def to_pandas(self):
        """The launches as a pandas DataFrame, one row a launch in the seed's order: its inputs as
        run, z_s, verdict, floats, flight_time (`launches`), the units in `df.attrs["units"]`
        (needs pandas; no rows where the scene's top cannot hover)."""
        from levitron.runtime.ui import frames
        return frames.frame(self.launches, self.column_units(), "LaunchOdds.to_pandas()", scene=self.scene)
