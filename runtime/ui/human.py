"""Numbers with units for people: the human view of every command (JSON stays SI, unformatted).

    u = Units.of_scene(scene)    # SI scene (cm, g, Hz, rpm) or dimensionless (scene units)
    u.length(0.1574)  -> "15.74 cm"          u.mass(0.0515) -> "51.5 g"
    u.rate(459.6)     -> "460 rad/s (73.2 Hz, 4390 rpm)"
    u.value(3.06, "N/m") -> "3.06 N/m"   u.label("spin", "rad/s") -> "spin (rad/s)"
    sig(1.5141e-10)   -> "1.5e-10"

This is the one unit system of every view: text, plots and the report. Which units: the scene's
`units` key ("SI" or "dimensionless") where it gives one, else SI when its gravity is Earth's,
9 <= g <= 10.5 m/s^2 (the scene key `g`, default 9.81); any other g (a dimensionless scene has
g = 1) is shown in the scene's own units: plain numbers without cm, g, s, Hz, N/m or A m^2, rates
in rad per time unit, times in time units (angles stay rad and deg: they have no units). Wall
times (`duration`) are the computer's, in seconds in every scene. No number is printed with more
than 6 significant digits (4 by default).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

G_SI = (9.0, 10.5)     # m/s^2: the range of g that marks a scene as SI
SI_SYMBOLS = frozenset({"m", "cm", "mm", "um", "kg", "g", "s", "ms", "m/s", "N", "N/m", "J", "J m", "A",
                        "A m^2", "kg m^2", "m/s^2", "A/m", "T m", "T", "mT", "Hz", "rpm", "rad/s"})


def sig(v, digits: int = 4) -> str:
    """`v` to `digits` significant digits (at most 6), without trailing zeros; None/NaN -> "n/a"."""
    if v is None:
        return "n/a"
    v = float(v)
    if not math.isfinite(v):
        return "n/a" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    digits = max(1, min(6, digits))
    if v == 0:
        return "0"
    mag = math.floor(math.log10(abs(v)))
    if -4 <= mag < 6:
        decimals = digits - 1 - mag
        v = round(v, decimals)
        decimals = max(0, decimals)
        text = f"{v:.{decimals}f}"
        if "." in text:
            text = text.rstrip("0").rstrip(".")
        return text
    mant, exp = f"{v:.{digits - 1}e}".split("e")
    if "." in mant:
        mant = mant.rstrip("0").rstrip(".")
    return f"{mant}e{int(exp)}"


def span(lo, hi, fmt) -> str:
    """"lo-hi unit" from a formatter that returns "number unit"."""
    a, b = fmt(lo), fmt(hi)
    ua, ub = a.partition(" ")[2], b.partition(" ")[2]
    if ua == ub:               # one unit (or none: a dimensionless scene)
        return f"{a.partition(' ')[0]}-{b}"
    return f"{a} to {b}"


def duration(t) -> str:
    """A wall time or a run length in seconds: "7 ms", "4.2 s", "3 min 5 s", "5 h 12 min",
    "12.3 days", "84 years"."""
    if t is None:
        return "n/a"
    t = float(t)
    if not math.isfinite(t):
        return f"{t} s"
    if t >= 365.25 * 86400:
        return f"{sig(t / (365.25 * 86400), 3)} years"
    if t >= 86400:
        return f"{sig(t / 86400, 3)} days"
    if round(t / 60) >= 60:
        h, m = divmod(round(t / 60), 60)
        return f"{h} h {m} min"
    if t < 1e-3:
        return f"{sig(t * 1e6, 3)} us"
    if t < 1:
        return f"{sig(t * 1e3, 3)} ms"
    if t < 120:
        return f"{sig(t, 3)} s"
    m, sec = divmod(round(t), 60)
    return f"{m} min {sec} s"


@dataclass(frozen=True)
class Units:
    """How a scene's numbers are shown: SI scenes in cm, g, Hz/rpm; other scenes in their own units."""

    si: bool

    @classmethod
    def of(cls, g) -> Units:
        """SI when G_SI[0] <= g <= G_SI[1] (Earth's gravity in m/s^2); otherwise scene units."""
        return cls(si=g is not None and G_SI[0] <= abs(float(g)) <= G_SI[1])

    @classmethod
    def of_scene(cls, scene) -> Units:
        """The scene's `units` key when it gives one, else the g rule of `of`."""
        stated = (getattr(scene, "data", None) or {}).get("units")
        if stated is not None:
            return cls(si=stated == "SI")
        return cls.of(scene.params.get("g", 9.81))

    def unit(self, si_unit: str) -> str:
        """The shown unit of a quantity whose SI unit (the JSON's) is `si_unit`: itself in an SI
        scene ("1" -> ""); in a dimensionless scene "" for everything but angles and rates."""
        if si_unit in ("1", ""):
            return ""
        if self.si or si_unit not in SI_SYMBOLS:       # angles, "fraction of z_s": no scene units
            return si_unit
        return {"rad/s": "rad/time", "s": "time units"}.get(si_unit, "")

    def named(self, si_unit: str) -> str:
        """The unit a JSON field or a result's message names: `si_unit` itself in an SI scene; in a
        dimensionless scene the scene's ("rad/time", "time units", "scene units"; angles and "1"
        as they are)."""
        if self.si or si_unit in ("1", ""):
            return si_unit
        return self.unit(si_unit) or "scene units"

    def value(self, v, si_unit: str, digits: int = 4) -> str:
        """A number with its shown unit (unit)."""
        return f"{sig(v, digits)} {self.unit(si_unit)}".rstrip()

    def label(self, name: str, si_unit: str) -> str:
        """An axis label: "spin (rad/s)", "mass (kg)"; "spin (rad/time)", "mass (scene units)"."""
        shown = self.unit(si_unit)
        if not shown and si_unit not in ("1", ""):
            shown = "scene units"
        return f"{name} ({shown})" if shown else name

    def top(self, m) -> str:
        """"the 51.5 g top" (SI) or "the top of mass 1" (a bare number reads badly before "top")."""
        return f"the {self.mass(m)} top" if self.si else f"the top of mass {self.mass(m)}"

    @property
    def note(self) -> str:
        return "" if self.si else "(dimensionless scene: numbers in the scene's own units)"

    @staticmethod
    def _length_unit(v) -> tuple[float, str]:
        """The factor and unit a length of size |v| is shown in (SI): m, cm, mm or um."""
        if abs(v) >= 1 or v == 0:
            return 1.0, "m"
        if abs(v) >= 0.01:
            return 100.0, "cm"
        if abs(v) >= 1e-5:
            return 1e3, "mm"
        if abs(v) >= 1e-9:
            return 1e6, "um"
        return 1.0, "m"                      # below a nanometre: round-off scale, plain metres

    def length(self, v, digits: int = 4) -> str:
        if v is None:
            return "n/a"
        if not self.si:
            return sig(v, digits)
        k, unit = self._length_unit(v)
        return f"{sig(v * k, digits)} {unit}"

    def length_span(self, lo, hi, digits: int = 4) -> str:
        """A range of lengths in one unit, the larger end's: "9.948-11.02 cm", "1-1.319 mm"."""
        if not self.si:
            return f"{sig(lo, digits)}-{sig(hi, digits)}"
        k, unit = self._length_unit(max(abs(lo), abs(hi)))
        return f"{sig(lo * k, digits)}-{sig(hi * k, digits)} {unit}"

    def mass(self, v, digits: int = 4) -> str:
        if not self.si:
            return sig(v, digits)
        return f"{sig(v * 1e3, digits)} g" if abs(v) < 1 else f"{sig(v, digits)} kg"

    def rate(self, w, digits: int = 4) -> str:
        """An angular rate: rad/s with Hz and rpm beside (SI); scene units otherwise."""
        if w is None:
            return "n/a"
        if not self.si:
            return f"{sig(w, digits)} rad/time"
        return (f"{sig(w, digits)} rad/s ({sig(w / (2 * math.pi), 3)} Hz, "
                f"{sig(w * 60 / (2 * math.pi), 3)} rpm)")

    def rate_span(self, lo, hi, digits: int = 4) -> str:
        """"lo-hi rad/s (... Hz, ... rpm)"; a narrow span gets more digits (up to sig's 6) until
        its two ends differ, never a span printed as a point."""
        if not self.si:
            return f"{apart(lo, hi, digits)} rad/time"
        hz = 2 * math.pi
        return (f"{apart(lo, hi, digits)} rad/s ({apart(lo / hz, hi / hz, 3)} Hz, "
                f"{apart(lo * 60 / hz, hi * 60 / hz, 3)} rpm)")

    def time(self, t) -> str:
        return duration(t) if self.si else f"{sig(t, 4)} time units"

    def angle(self, a) -> str:
        """Radians with degrees beside (angles have no scene units)."""
        return f"{sig(a, 3)} rad ({sig(math.degrees(a), 3)} deg)"

    def field(self, b) -> str:
        if not self.si:
            return sig(b, 4)
        return f"{sig(b * 1e3, 4)} mT" if abs(b) < 1 else f"{sig(b, 4)} T"


def quantity(units: Units, value: float, si_unit: str, fmt: str = ".6g") -> str:
    """A number and its unit as the scene shows it: "0.106 m" (SI), "0.106" in a dimensionless
    scene, where a rate is "rad/time" and a time "time units" (the answers' repr and message)."""
    return f"{value:{fmt}} {units.unit(si_unit)}".rstrip()


def apart(lo, hi, digits: int = 4) -> str:
    """"lo-hi" at `digits` significant digits, or more (up to 6) where the ends would print alike."""
    d = digits
    while d < 6 and lo != hi and sig(lo, d) == sig(hi, d):
        d += 1
    return f"{sig(lo, d)}-{sig(hi, d)}"


def lines(*items) -> str:
    """The non-empty items, one a line."""
    return "\n".join(str(i) for i in items if i)
