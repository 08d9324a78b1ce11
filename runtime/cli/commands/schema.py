"""`levitron schema [COMMAND]`: the JSON Schema (draft 2020-12) of a command's `--json` answer
(runtime/cli/schema.py builds it from the answer types), or without COMMAND the commands that have one.

The plain view of `levitron schema COMMAND` is the schema itself, so `levitron schema stability > s.json`
is a schema file; with --json it is the answer object {command, schema} (with provenance and success, as
every --json answer)."""
from __future__ import annotations

import json

from levitron.runtime.ui.human import lines

NAME = "schema"
HELP = "the JSON Schema of a command's --json answer (without COMMAND: the commands that have one)"
EXAMPLE = "levitron schema stability > stability.schema.json"
TAKES_SCENE = False       # no SCENE, --set or --temperature (runtime/cli/main.py)


def add_arguments(parser) -> None:
    from levitron.runtime.cli.commands import COMMANDS
    parser.add_argument("command_name", nargs="?", default=None, metavar="COMMAND", choices=COMMANDS,
                        help="a command: its --json answer's schema (default: list the commands)")


def run(args) -> dict:
    from levitron.runtime.cli import schema
    if args.command_name is None:
        from levitron.runtime.cli.main import command_help
        return {"commands": [{"command": c, "description": command_help(c)} for c in schema.commands()]}
    return {"command": args.command_name, "schema": schema.schema(args.command_name)}


def human(r: dict, scene=None) -> str:
    """The schema as JSON (a file's text), or one line a command."""
    if "schema" in r:
        return json.dumps(r["schema"], indent=2)
    width = max(len(c["command"]) for c in r["commands"])
    return lines("the commands whose --json answer has a schema (`levitron schema COMMAND` prints it):",
                 *[f"  {c['command']:<{width}}  {c['description']}" for c in r["commands"]])
