"""A dimensionless scene (`units = "dimensionless"`, g = 1: the thesis's annulus in its own units) and
si_units(text), the SI units a text shows after a number or inside an axis label's brackets (wall
times, the computer's, excepted): what the tests of "a dimensionless scene never shows an SI unit" share."""
from __future__ import annotations

import re

SCENE = """name = "unit_annulus"
g = 1.0
units = "dimensionless"

[top]
mass = 1.0
A = 0.01
C = 0.006

[plate]
kind = "annulus"
radius = 1.0
hole = 0.3
murho = -0.51915

[field]
order = 2

[model]
needs = ["reduced", "full", "linear"]
"""

# an SI unit after a number or inside the brackets of an axis label
SI = r"A m\^2|kg m\^2|m/s\^2|m/s|A/m|T m|J m|degC|rad/s|N/m|cm|mm|um|mN|mT|ms|kg|Hz|rpm|m|g|s|N|T|A"   # longest first
AFTER_NUMBER = re.compile(rf"\d\s?({SI})(?![\w^/])")     # the unit, group 1
IN_LABEL = re.compile(rf"\(({SI})(?:,[^)]*)?\)")
WALL = re.compile(r"\d+(\.\d+)? (us|ms|s|min)( \d+ s)? of wall time|\d+(\.\d+)? (us|ms|s) per call")


def si_units(text: str) -> list[str]:
    text = WALL.sub("", text)
    return [m.group(1) for m in AFTER_NUMBER.finditer(text)] + [m.group(0) for m in IN_LABEL.finditer(text)]
