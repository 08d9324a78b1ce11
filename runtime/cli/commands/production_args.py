"""The flags of a production run (--kit, --washers, --kits), shared by `optimize --maximize yield`
and `compare` (runtime/design/production.py's Production), over the scene's [production] table."""
from __future__ import annotations

from levitron.runtime.errors import UserError


def add_production_arguments(group) -> None:
    group.add_argument("--kit", action="append", default=[], metavar="INPUT=SPREAD",
                       help="a kit's manufacturing spread, relative: strength=rel:normal:0,0.02 (the magnets, "
                            "default 2 %%) or mass=rel:normal:0,0.003 (the top, default 0.3 %%); or of a scene key "
                            "that is a model parameter, as a deviation: plate.thickness=abs:normal:0,0.0002 (SI) or "
                            "plate.remanence=rel:normal:0,0.02 (repeatable; over the scene's [production] kit)")
    group.add_argument("--washers", default=None, metavar="M1,M2,...",
                       help="the washers in each box, masses in kg or with a unit (e.g. '0.2 g,0.4 g,0.8 g'): "
                            "each owner puts on the subset with which the top floats most often (default: the "
                            "scene's [production] washers, else none)")
    group.add_argument("--kits", type=int, default=None, metavar="N",
                       help="kits of the production run, one launch each (default: the scene's [production] "
                            "kits, else 300)")


def given(args) -> list[str]:
    """The production flags given."""
    return [f for f, v in (("--kit", args.kit), ("--washers", args.washers), ("--kits", args.kits)) if v]


def production_of(args, seed: int, table=None):
    """The production run the flags describe, over the scene's [production] table (`table`), over
    the defaults."""
    from levitron.runtime.design.production import Production
    kit = {}
    for item in args.kit:
        name, sep, spec = item.partition("=")
        if not sep:
            raise UserError(f"--kit {item}: write INPUT=SPREAD, e.g. --kit strength=rel:normal:0,0.02")
        kit[name.strip()] = spec.strip()
    washers = None if args.washers is None else [_mass(w) for w in args.washers.split(",") if w.strip()]
    return Production.of(kit, washers, args.kits, seed, table)


def _mass(text: str) -> float:
    """A washer's mass: a number (SI) or a quantity with a unit (scene/quantity.py)."""
    from levitron.scene import quantity
    text = text.strip()
    try:
        return quantity.si_value(text, "kg", "--washers") if quantity.has_unit(text) else float(text)
    except ValueError:
        raise UserError(f"--washers {text!r} is not a mass: give numbers (SI) or masses with a unit, e.g. "
                        "--washers '0.2 g,0.5 g'") from None
