"""`levitron keys [KIND]`: the keys a scene file takes, from the scene's own tables (scene/keys.py,
the plate registry scene/plates/; scene/plates/docs.py key_table): name, unit, meaning, default or
required. Without KIND the plate kinds and the keys of every other section; with it that kind's
[plate] keys."""
from __future__ import annotations

from levitron.scene.plates import KINDS
from levitron.scene.plates.docs import key_table

from levitron.runtime.cli.suggest import closest
from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import lines

NAME = "keys"
HELP = ("the keys of a scene file: the plate kinds and the common sections (top, field, model, launch ...), "
        "or with KIND that plate kind's keys; name, unit, meaning, default or required")
EXAMPLE = "levitron keys annulus"
TAKES_SCENE = False       # no SCENE, --set or --temperature (runtime/cli/main.py)


def add_arguments(parser) -> None:
    parser.add_argument("kind", nargs="?", default=None, metavar="KIND",
                        help=f"a plate kind: {', '.join(KINDS)} (default: the kinds and the other sections)")


def run(args) -> dict:
    if args.kind is not None and args.kind not in KINDS:
        guess = closest(args.kind, KINDS)
        raise UserError(f"unknown plate kind {args.kind!r}: use one of {', '.join(KINDS)}"
                        + (f" (did you mean {guess}?)" if guess else ""))
    return key_table(args.kind)


def status(row: dict) -> str:
    """required, default, or the keys it stands in for: one short phrase."""
    others = " or ".join(row["alternatives"])
    if row["required"]:
        return f"required (or {others})" if others else "required"
    if row["default"] is not None:
        return f"default {row['default']}"
    return f"instead of {others}" if others else "optional"


def _rows(rows: list[dict], indent: str = "  ") -> list[str]:
    name = max((len(r["name"]) for r in rows), default=0)
    unit = max((len(r["unit"] or "-") for r in rows), default=0)
    state = max((len(status(r)) for r in rows), default=0)
    return [f"{indent}{r['name']:<{name}}  {r['unit'] or '-':<{unit}}  {status(r):<{state}}  {r['meaning']}"
            for r in rows]


def human(r: dict, scene=None) -> str:
    """The keys as a table a line each: name, unit (SI), required or default, meaning."""
    common = ("every kind also takes: "
              + ", ".join(f"{c['name']} ({c['unit']})" for c in r["plate_common"])
              + " (`levitron keys` describes them)")
    if r["kind"] is not None:
        decisions = [f"structural decision {k}: {v}" for k, v in r["decisions"].items()]
        return lines(f"[plate] kind = \"{r['kind']}\": {r['doc']}", *_rows(r["keys"]), common, *decisions,
                     "" if r["can_be_part"] else "not allowed as a part of a compound plate",
                     "example:", *[f"  {ln}" for ln in r["example"].splitlines()])
    width = max(len(k) for k in r["kinds"])
    out = ["plate kinds (`levitron keys KIND` lists a kind's keys):",
           *[f"  {k:<{width}}  {doc}" for k, doc in r["kinds"].items()],
           "[plate] keys of every kind:", *_rows(r["plate_common"])]
    for section, rows in r["sections"].items():
        out += ["the top level:" if section == "scene" else f"[{section}]:", *_rows(rows)]
    return lines(*out, "numbers are SI (or a dimensionless scene's own units); "
                 "a scene's values can be changed on the command line with --set SECTION.KEY=VALUE")
