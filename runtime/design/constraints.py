"""`--constrain EXPR`: a small safe grammar (never evaluated as Python): NAME >= NUMBER or
NAME <= NUMBER, NAME one of the stability quantities of runtime/design/optimize.py (SI units)."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

from levitron.runtime.errors import UserError
from levitron.runtime.ui.validate import number_text

QUANTITIES = {
    "z_s": "hover height (m), thesis 3.3.2",
    "stiffness": "vertical stiffness U''(z_s) = mu Phi_3 (N/m), thesis 3.3.3",
    "sigma_lo": "lowest stabilising spin (rad/s), thesis 3.3.16",
    "sigma_hi": "highest stabilising spin (rad/s), thesis 3.3.16",
}
_FORM = re.compile(r"\s*([A-Za-z_]+)\s*(>=|<=)\s*([-+0-9.eE]+)\s*\Z")


@dataclass(frozen=True)
class Constraint:
    name: str
    op: str           # ">=" | "<="
    bound: float

    @classmethod
    def parse(cls, text: str) -> Constraint:
        m = _FORM.match(text or "")
        names = ", ".join(QUANTITIES)
        if not m:
            raise UserError(f"«constrain» {text!r}: write NAME>=NUMBER or NAME<=NUMBER with NAME one "
                            f"of {names}, e.g. stiffness>=1")
        name, op, num = m.groups()
        if name not in QUANTITIES:
            raise UserError(f"«constrain» {text!r}: unknown quantity {name!r}; use one of {names}")
        try:
            bound = number_text(num.strip())
        except ValueError:
            bound = math.nan
        if not math.isfinite(bound):
            raise UserError(f"«constrain» {text!r}: {num!r} is not a finite number")
        return cls(name, op, bound)

    def margin(self, value: float) -> float:
        """>= 0 when satisfied."""
        return value - self.bound if self.op == ">=" else self.bound - value

    def __str__(self) -> str:
        return f"{self.name}{self.op}{self.bound:g}"
