"""The spread language of the launch inputs: "normal:MEAN,SD", "uniform:LO,HI" or a number, and
for mass and strength the relative spelling "rel:..." (runtime/scan/launch_odds.py samples them).

Every refusal quotes the input as the user typed it (never a form the parser made of it), and
`check_support` holds a spread's whole support (a normal's mean +- SUPPORT_SDS sd) to its key's
bound (scene/keys.py Bound), the same bound the key's own value is held to.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.words import si, si_unit
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


def typed_text(spec) -> str:
    """The input as the user typed it, for a refusal: a text quoted as given, a number as a number."""
    return repr(spec.strip()) if isinstance(spec, str) else repr(spec)


def parse_dist(name: str, spec, typed=None, table: bool = False) -> Dist:
    """ "normal:MEAN,SD" | "uniform:LO,HI" | a number -> Dist (one-line UserError otherwise,
    quoting `typed`: the input as typed where spec is a part of it, e.g. the body of a rel: spec;
    table: it came from the scene's [launch] table, and the refusal says so)."""
    how = (f'write e.g. {name} = "normal:MEAN,SD", "uniform:LO,HI" or a number in the scene\'s [launch] table'
           if table else f"write e.g. «{name}» normal:MEAN,SD, uniform:LO,HI or a number")
    said = f"{'[launch]' if table else 'launch'} {name} = {typed_text(spec if typed is None else typed)}"
    if isinstance(spec, bool):
        raise UserError(f"{said} is not a distribution: {how}")
    if isinstance(spec, (int, float)):
        try:
            value = float(spec)
        except OverflowError:             # an integer beyond any double (the API's 10**400)
            value = math.inf
        if not math.isfinite(value):
            raise UserError(f"{said} is not finite: {how}")
        return Dist("fixed", value)
    if not isinstance(spec, str):         # a TOML array or table, or an API object
        raise UserError(f"{said} is not a distribution: {how}")
    text = str(spec).strip()
    kind, sep, args = text.partition(":")
    if not sep:
        try:
            return parse_dist(name, number_text(text), spec if typed is None else typed, table)
        except ValueError:
            raise UserError(f"{said} is not a distribution: {how}") from None
    kind = kind.strip().lower()
    if kind not in ("normal", "uniform"):
        raise UserError(f"{said}: unknown distribution {kind!r}: use normal or uniform ({how})")
    try:
        a, b = (number_text(v.strip()) for v in args.split(","))
    except ValueError:
        raise UserError(f"{said} needs two numbers after '{kind}:': {how}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise UserError(f"{said} has a number that is not finite: {how}")
    return checked(name, kind, a, b, said)


def checked(name: str, kind: str, a: float, b: float, said: str) -> Dist:
    """Dist(kind, a, b) once its two numbers make sense (`said`: the input as typed, for the error)."""
    if kind == "normal" and b < 0:
        raise UserError(f"{said}: the standard deviation {b:g} is negative; give SD >= 0")
    if kind == "uniform" and b < a:
        raise UserError(f"{said}: the range {a:g},{b:g} is reversed; give LO <= HI")
    return Dist(kind, a + 0.0, b + 0.0)    # -0.0 as 0.0: numpy's uniform refuses hi - lo = -0.0


REL = "rel:"          # a relative spread of mass or strength says so: rel:normal:0,0.002, rel:0.2%
RELATIVE = ("mass", "strength")


def parse_input(name: str, spec, reference: float | None = 1.0, table: bool = False) -> Dist:
    """One input's spec -> the Dist monte_carlo samples. Mass and strength are sampled as relative
    deviations d (m (1 + d), mu (1 + d)) but given either way, and the spelling says which:
    "rel:normal:0,0.002", "rel:uniform:-0.01,0.01", "rel:0.2%" (normal, sd 0.2 %) or "rel:-0.001"
    are relative; "normal:0.02135,0.0002" is the mass itself in kg (reference: the scene's mass)
    and "normal:1,0.005" the magnets' strength as a factor (reference 1). An absolute spec whose
    centre is not within a factor 2 of the reference is refused with the relative spelling: a
    mass spread given as a deviation (normal:0,0.002) is not silently a 0 kg top. reference None:
    the spelling alone is checked (the scene's [launch] table read before a model, table=True)."""
    if name not in RELATIVE:
        return parse_dist(name, spec, table=table)
    text = spec.strip() if isinstance(spec, str) else spec
    if isinstance(text, str) and text.lower().startswith(REL):
        body = text[len(REL):].strip()
        if body.endswith("%"):
            try:
                sd = number_text(body[:-1].strip()) / 100
            except ValueError:
                raise UserError(f"launch {name} = {typed_text(spec)}: write rel:SD% with a number, e.g. "
                                "rel:0.2%") from None
            if not math.isfinite(sd):
                raise UserError(f"launch {name} = {typed_text(spec)} has a number that is not finite: "
                                "write rel:SD% with a number, e.g. rel:0.2%")
            if sd < 0:
                raise UserError(f"launch {name} = {typed_text(spec)}: the standard deviation {body} is "
                                "negative; give SD >= 0, e.g. rel:0.2%")
            return Dist("normal", 0.0, sd + 0.0)
        return parse_dist(name, body, spec, table)
    d = parse_dist(name, spec, table=table)
    if reference is None:
        return d
    centre = 0.5 * (d.a + d.b) if d.kind == "uniform" else d.a
    what = f"the mass in {si_unit('kg')}" if name == "mass" else "the magnets' strength as a factor (1 = the scene's)"
    if not (0.5 * reference < centre < 2 * reference):
        flag = f"«{name}»"
        raise UserError(f"launch {name} = {typed_text(spec)} reads as {what}, centred at {centre:g}, not near "
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


SUPPORT_SDS = 8.0       # a normal spread's support: mean +- 8 sd (a draw beyond it: about 1e-15)


def support(d: Dist) -> tuple[float, float]:
    """The values a spread draws: a normal's mean +- SUPPORT_SDS sd, a uniform's range, the fixed value."""
    if d.kind == "normal":
        return d.a - SUPPORT_SDS * d.b, d.a + SUPPORT_SDS * d.b
    return (d.a, d.b) if d.kind == "uniform" else (d.a, d.a)


def check_support(name: str, d: Dist, typed, bound, unit: str, what: str = "") -> None:
    """One-line UserError where a draw of `d` (its `support`) leaves `bound` (scene/keys.py Bound),
    quoting the input as `typed` and the bound as it reads; `what` says what such a value means."""
    lo, hi = support(d)
    out = bound.first_outside(lo, hi)
    if out is None:
        return
    reach = (f"a relative deviation of {100 * out:.4g} %" if unit == "1"
             else si(out, unit) if unit else f"{out:g}")
    sds = f" (mean +- {SUPPORT_SDS:g} sd)" if d.kind == "normal" and d.b > 0 else ""
    raise UserError(f"«{name}» {str(typed).strip()} reaches {reach}{sds}, outside {bound.text}"
                    f"{what}: give a spread inside it")
