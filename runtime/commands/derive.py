"""`levitron derive [SCENE ...]`: regenerate models (the same as `make derive`)."""
from __future__ import annotations

import json
import subprocess
import sys

from ..errors import UserError
from ..model import ROOT

NAME = "derive"
HELP = "regenerate the generated models of the given scenes (default: all)"
MULTI_SCENE = True


def add_arguments(parser) -> None:
    parser.add_argument("--force", action="store_true", help="derive even when nothing changed")


def run(args) -> dict:
    # derive runs in its own process: the runtime never imports sympy.
    cmd = [sys.executable, "-m", "derive", *args.scenes, "--json"]
    for s in args.set:
        cmd += ["--set", s]
    if args.force:
        cmd.append("--force")
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=False)
    if res.returncode != 0:
        raise UserError(res.stderr.strip().removeprefix("error: ") or "derive failed")
    return json.loads(res.stdout)
