"""The spread language of the launch inputs: "normal:MEAN,SD", "uniform:LO,HI" or a number, and
for mass and strength the relative spelling "rel:..." (runtime/scan/launch_odds.py samples them).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.words import si_unit
from levitron.runtime.ui.validate import number_text


@dataclass(frozen=True)
class Dist:
    """One input's distribution: kind "normal" (a = mean, b = sd), "uniform" (a = lo, b = hi) or
    "fixed" (a)."""
    kind: str
    a: float
    b: float = 0.0

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        if self.kind == "normal":
            return rng.normal(self.a, self.b, n) if self.b > 0 else np.full(n, self.a)
        if self.kind == "uniform":
            return rng.uniform(self.a, self.b, n)
        return np.full(n, self.a)

    @property
    def spread(self) -> bool:
        return (self.kind == "normal" and self.b > 0) or (self.kind == "uniform" and self.b > self.a)

    def text(self) -> str:
        return {"normal": f"normal:{self.a:g},{self.b:g}", "uniform": f"uniform:{self.a:g},{self.b:g}",
                "fixed": f"{self.a:g}"}[self.kind]


def parse_dist(name: str, spec) -> Dist:
    """ "normal:MEAN,SD" | "uniform:LO,HI" | a number -> Dist (one-line UserError otherwise)."""
    how = f"write e.g. «{name}» normal:MEAN,SD, uniform:LO,HI or a number"
    if isinstance(spec, bool):
        raise UserError(f"launch {name} = {spec!r} is not a distribution: {how}")
    if isinstance(spec, (int, float)):
        try:
            value = float(spec)
        except OverflowError:             # an integer beyond any double (the API's 10**400)
            value = math.inf
        if not math.isfinite(value):
            raise UserError(f"launch {name} = {spec} is not finite: {how}")
        return Dist("fixed", value)
    if not isinstance(spec, str):         # a TOML array or table, or an API object
        raise UserError(f"launch {name} = {spec!r} is not a distribution: {how}")
    text = str(spec).strip()
    kind, sep, args = text.partition(":")
    if not sep:
        try:
            return parse_dist(name, number_text(text))
        except ValueError:
            raise UserError(f"launch {name} = {text!r} is not a distribution: {how}") from None
    kind = kind.strip().lower()
    if kind not in ("normal", "uniform"):
        raise UserError(f"launch {name}: unknown distribution {kind!r}: use normal or uniform ({how})")
    try:
        a, b = (number_text(v.strip()) for v in args.split(","))
    except ValueError:
        raise UserError(f"launch {name} = {text!r} needs two numbers after '{kind}:': {how}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise UserError(f"launch {name} = {text!r} has a number that is not finite: {how}")
    if kind == "normal" and b < 0:
        raise UserError(f"launch {name} = {text!r}: the standard deviation {b:g} is negative; give SD >= 0")
    if kind == "uniform" and b < a:
        raise UserError(f"launch {name} = {text!r}: the range {a:g},{b:g} is reversed; give LO <= HI")
    return Dist(kind, a + 0.0, b + 0.0)    # -0.0 as 0.0: numpy's uniform refuses hi - lo = -0.0


REL = "rel:"          # a relative spread of mass or strength says so: rel:normal:0,0.002, rel:0.2%
RELATIVE = ("mass", "strength")


def parse_input(name: str, spec, reference: float = 1.0) -> Dist:
    """One input's spec -> the Dist monte_carlo samples. Mass and strength are sampled as relative
    deviations d (m (1 + d), mu (1 + d)) but given either way, and the spelling says which:
    "rel:normal:0,0.002", "rel:uniform:-0.01,0.01", "rel:0.2%" (normal, sd 0.2 %) or "rel:-0.001"
    are relative; "normal:0.02135,0.0002" is the mass itself in kg (reference: the scene's mass)
    and "normal:1,0.005" the magnets' strength as a factor (reference 1). An absolute spec whose
    centre is not within a factor 2 of the reference is refused with the relative spelling: a
    mass spread given as a deviation (normal:0,0.002) is not silently a 0 kg top."""
    if name not in RELATIVE:
        return parse_dist(name, spec)
    text = spec.strip() if isinstance(spec, str) else spec
    if isinstance(text, str) and text.lower().startswith(REL):
        body = text[len(REL):].strip()
        if body.endswith("%"):
            try:
                sd = number_text(body[:-1].strip()) / 100
            except ValueError:
                raise UserError(f"launch {name} = {spec!r}: write rel:SD% with a number, e.g. rel:0.2%") from None
            return parse_dist(name, f"normal:0,{sd!r}")
        return parse_dist(name, body)
    d = parse_dist(name, spec)
    centre = 0.5 * (d.a + d.b) if d.kind == "uniform" else d.a
    what = f"the mass in {si_unit('kg')}" if name == "mass" else "the magnets' strength as a factor (1 = the scene's)"
    if not (0.5 * reference < centre < 2 * reference):
        flag = f"«{name}»"
        raise UserError(f"launch {name} = {spec!r} reads as {what}, centred at {centre:g}, not near "
                        f"{reference:g}: a relative spread says so, e.g. {flag} rel:normal:0,0.002 or "
                        f"{flag} rel:0.2%")
    if d.kind == "uniform":
        return Dist("uniform", d.a / reference - 1, d.b / reference - 1)
    return Dist(d.kind, d.a / reference - 1, d.b / reference)


def spec_text(name: str, d: Dist) -> str:
    """The spec that parse_input reads back as d, at full precision (mass, strength: relative)."""
    r = repr
    body = {"normal": f"normal:{r(d.a)},{r(d.b)}", "uniform": f"uniform:{r(d.a)},{r(d.b)}",
            "fixed": r(d.a)}[d.kind]
    return REL + body if name in RELATIVE else body
