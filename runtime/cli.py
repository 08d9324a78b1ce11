"""The `levitron` command: `levitron <command> SCENE [--set k=v ...] [--json]` (DESIGN.md).

With --json a command prints one JSON object on stdout and nothing else; logs go to stderr. Bad
input exits 2 with one line saying what is wrong and how to fix it.
"""
from __future__ import annotations

import argparse
import importlib
import json
import math
import sys

from derive.scene import SceneError

from .cbuild import CompileError
from .commands import COMMANDS
from .errors import UserError


def _modules():
    return [importlib.import_module(f"runtime.commands.{name}") for name in COMMANDS]


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="levitron", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for mod in _modules():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        if getattr(mod, "MULTI_SCENE", False):
            p.add_argument("scenes", nargs="*", metavar="SCENE", help="scene names or .toml paths")
        else:
            p.add_argument("scene", metavar="SCENE", help="a scene name in scenes/ or a .toml path")
        p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="override a scene key, e.g. --set top.mass=0.03 (repeatable)")
        p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return ap


def _clean(obj):
    """JSON-safe: NaN/inf never reach the output (they become null)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "tolist"):
        return _clean(obj.tolist())
    return obj


def _human(obj, indent: int = 0) -> str:
    pad = "  " * indent
    if isinstance(obj, dict):
        lines = []
        for k, v in obj.items():
            if isinstance(v, (dict, list)) and v and not all(isinstance(e, (int, float)) for e in v):
                lines.append(f"{pad}{k}:")
                lines.append(_human(v, indent + 1))
            else:
                lines.append(f"{pad}{k}: {json.dumps(v)}")
        return "\n".join(lines)
    if isinstance(obj, list):
        return "\n".join(f"{pad}- {json.dumps(v)}" for v in obj)
    return f"{pad}{obj}"


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        result = _clean(args._run(args))
    except (UserError, SceneError) as exc:
        print(f"levitron {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except CompileError as exc:
        print(f"levitron {args.command}: {exc}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(result))
    else:
        print(_human(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
