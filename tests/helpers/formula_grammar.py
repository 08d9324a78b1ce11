"""A small grammar of expression-plate formulas (phi0 or bz in z, b, c), seeded: the random
formula plates of tests/c/test_c_vs_casadi.py.

Every formula is finite and smooth for z > 0, b, c > 0 (so any disagreement between C and CasADi
is the emitter's, not the domain's), and carries constants of every magnitude the parser accepts:
small integers, whole numbers of 2^63 and more (the literals gcc used to wrap), 10^k for k up to
+-150, rationals and decimals. Each formula has at most two constants multiplied together, so no
product leaves double range.
"""
from __future__ import annotations

import random

BIG_WHOLE = ["2**63", "2**64", "3*2**70", "1e20", "18446744073709551616", "9223372036854775807",
             "1e19", "123456789012345678901234567890"]
FACTORS = ["sqrt(z**2 + c**2)", "exp(-z/c)", "log(z + c)", "atan(z/c)", "sin(z/c)", "cos(z/c)",
           "tanh(z/c)", "asinh(z/c)", "cosh(z/(3*c))", "(z**2 + c**2)**(-3/2)", "1/(z + c)**2",
           "z/sqrt(z**2 + c**2)", "atan2(z, c)", "(z + c)**(5/2)", "exp(-(z/c)**2)"]
BZ_FORMS = ["{k}*b*c**2/(z**2 + c**2)**(3/2)", "{k}*b*exp(-z/c)", "{k}*b/(z + c)**2",
            "{k}*b*z/(z**2 + c**2)**2", "{k}*b*(1/(z + c)**3 - 1/(z + 2*c)**3)"]


def constant(rng: random.Random) -> str:
    """A constant literal of some magnitude, as formula text."""
    kind = rng.random()
    if kind < 0.3:
        return rng.choice(BIG_WHOLE)
    if kind < 0.55:
        return f"1e{rng.randint(-150, 150)}"
    if kind < 0.7:
        return f"{rng.randint(1, 9)}.{rng.randint(0, 999)}e{rng.randint(-40, 40)}"
    if kind < 0.85:
        return f"({rng.randint(1, 99)}/{rng.randint(1, 97)})"
    return str(rng.randint(2, 12))


def phi0(rng: random.Random) -> str:
    """A phi0 formula: a sum of one or two terms, each constant * b * one or two factors."""
    terms = []
    for _ in range(rng.randint(1, 2)):
        factors = rng.sample(FACTORS, rng.randint(1, 2))
        terms.append(f"{constant(rng)}*b*" + "*".join(factors))
    return " + ".join(terms) if rng.random() < 0.7 else " - ".join(terms)


def bz(rng: random.Random) -> str:
    """A bz formula whose antiderivative sympy finds quickly."""
    return rng.choice(BZ_FORMS).format(k=constant(rng))


def formula_plates(n: int, seed: int) -> list[dict]:
    """n plate tables of kind "expression", about one in six given by bz."""
    rng = random.Random(seed)
    plates = []
    for _ in range(n):
        params = {"b": round(rng.uniform(0.5, 2.0), 6), "c": round(rng.uniform(0.3, 2.0), 6)}
        if rng.random() < 1 / 6:
            plates.append({"kind": "expression", "bz": bz(rng), "params": params})
        else:
            plates.append({"kind": "expression", "phi0": phi0(rng), "params": params})
    return plates
