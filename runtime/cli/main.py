"""The `levitron` command: `levitron <command> SCENE [--set k=v ...] [--json]` (the contract in the documentation).

With --json a command prints one JSON object on stdout and nothing else (its `success`: cli/success.py);
logs go to stderr. Without
it, the command's human view (its module's `human(result, scene)`: the answer first, in cm, g, Hz
and rpm for SI scenes, runtime/ui/human.py), in colour on a terminal (rich), plain otherwise. Progress
(runtime/ui/progress.py) goes to stderr only, and only on a terminal without --json or --quiet.
Every failure is one line on stderr: bad input (a scene, an option, a path, the cache) exits 2 with
what is wrong and how to fix it; an unexpected exception is a bug and exits 3 with its type and
message (LEVITRON_DEBUG=1 shows the traceback). A closed stdout (`levitron ... | head -1`) ends
the command quietly. Ctrl-C (SIGINT) and SIGTERM stop any command within seconds, its worker
processes killed with it (runtime/model/processes.py): "levitron CMD: interrupted", exit 130 or 143.
"""
from __future__ import annotations

import argparse
import importlib
import json
import math
import os
import sys
import textwrap

from levitron.runtime.ui import progress
from levitron.runtime.ui import provenance
from levitron.runtime.ui.provenance import version
from levitron.runtime.cli.commands import COMMANDS
from levitron.runtime.cli import suggest
from levitron.runtime.errors import UserError
from levitron.runtime.words import render as words, speak
from levitron.runtime.cli.success import success as success_of

# scene.load (SceneError) and runtime.model (the compiler, process control) are imported where
# they are used: `levitron --version` and `--help` need neither (a tenth of a second of imports)

EXIT_USER = 2        # bad input: the message says what to fix
EXIT_INTERNAL = 3    # a bug: please report it
EXIT_INTERRUPTED = 130   # 128 + SIGINT; a SIGTERM exits 143 (runtime/model/processes.py)


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit 2): no usage block, a pointer to --help instead."""

    def error(self, message):
        self.exit(EXIT_USER, f"{self.prog}: error: {suggest.choice_hint(message)} (see `{self.prog} --help`)\n")

    def parse_args(self, args=None, namespace=None):
        """argparse's, with "did you mean --flag?" for a misspelt flag (runtime/cli/suggest.py)."""
        namespace, extras = self.parse_known_args(args, namespace)
        if extras:
            self.exit(EXIT_USER, suggest.unrecognized(self, namespace, extras))
        return namespace




def _modules(names=COMMANDS):
    return [importlib.import_module(f"levitron.runtime.cli.commands.{name}") for name in names]


def command_help(name: str) -> str:
    """A command module's HELP, read from its source without importing it (the module loads
    numpy, casadi ...; `levitron --help` needs only this line of each)."""
    import ast
    import importlib.util
    origin = importlib.util.find_spec(f"levitron.runtime.cli.commands.{name}").origin
    with open(origin, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), origin)
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "HELP" for t in node.targets):
            return ast.literal_eval(node.value)
    raise LookupError(f"{origin}: no HELP = '...' at the top level")


class _HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """The help text wrapped between words only: a flag or an objective (spin-ratio, --success-time)
    is never split at its hyphen, so what --help shows can be copied as it reads."""

    def _split_lines(self, text, width):
        return textwrap.wrap(" ".join(text.split()), width, break_on_hyphens=False)


def build_parser(only: str | None = None, overview: bool = False) -> argparse.ArgumentParser:
    """The parser of every command, or with `only` of that one command alone (a one-shot command
    then imports only its own module: `levitron stability` loads no design, scan or report code).
    With `overview` the commands are names and help lines only, their modules not imported: enough
    for `levitron --help` and for a missing command, and the same text as the full parser's."""
    ap = Parser(prog="levitron", description=__doc__.splitlines()[0])
    ap.add_argument("--version", action="version", version=f"levitron {version()}")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    if overview:
        for name in COMMANDS:
            sub.add_parser(name, help=command_help(name))
        return ap
    for mod in _modules((only,) if only in COMMANDS else COMMANDS):
        example = getattr(mod, "EXAMPLE", None)
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP,
                           epilog=f"example:\n  {example}" if example else None,
                           formatter_class=_HelpFormatter)
        takes_scene = getattr(mod, "TAKES_SCENE", True)      # `levitron scenes`, `keys` take none
        if getattr(mod, "MULTI_SCENE", False):
            p.add_argument("scenes", nargs="*", metavar="SCENE", help="scene names or .toml paths")
        elif takes_scene:
            p.add_argument("scene", metavar="SCENE",
                           help="a shipped scene's name (`levitron scenes` lists them) or a .toml path")
        if takes_scene:
            p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                           help="override a scene key, e.g. --set top.mass=0.03 (repeatable; "
                                "`levitron keys` lists the keys)")
        if takes_scene and not getattr(mod, "MULTI_SCENE", False):
            p.add_argument("--temperature", type=float, default=None, metavar="DEGC",
                           help="the magnets' temperature, degC (the scene key `temperature`: "
                                "plate/top temperature_coefficient scale their strength from 20 degC)")
        p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
        p.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
        mod.add_arguments(p)
        for action in p._actions:        # every number flag read as runtime/ui/validate.py reads numbers
            action.type = _quantity(action.dest) if action.type is float else {int: _int}.get(action.type, action.type)
        p.set_defaults(_run=mod.run, _module=mod)
    return ap


def _float(text: str) -> float:
    from levitron.runtime.ui.validate import number_text
    return number_text(text)


def _int(text: str) -> int:
    from levitron.runtime.ui.validate import count_text
    return count_text(text)


_float.__name__, _int.__name__ = "float", "int"      # argparse's "invalid float value: '1_0'"


def _quantity(dest: str):
    """The reader of number flag `dest`: a bare number as `_float` reads it (SI, the same path as
    ever), or one number with a unit ("30 Hz", "3 mm") in the flag's SI unit (scene/quantity.py)."""
    def float(text: str):      # named so: argparse's "invalid float value: '1_0'"
        from levitron.scene import quantity
        try:
            return quantity.typed_setting(text, dest) if quantity.has_unit(text) else _float(text)
        except quantity.SceneError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
    return float


def _typed_inputs(args) -> None:
    """scene/quantity.py at the edge: a scene's bare number that reads as grams or millimetres meant is
    warned of on stderr; a flag typed with a unit is refused in a dimensionless scene, else made a float."""
    from levitron.scene.quantity import Typed
    for note in getattr(_scene_or_none(args), "notes", ()):
        if note.startswith("warning: "):
            print(f"levitron {args.command}: {note}", file=sys.stderr)
    for name, v in [(k, v) for k, v in vars(args).items() if isinstance(v, Typed)]:
        if not getattr(_scene_units(args), "si", True):
            raise UserError(f"--{name.replace('_', '-')} {v.text!r}: this scene is dimensionless: give the "
                            "number in the scene's own units, without a unit")
        setattr(args, name, float(v))


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


def _dump(obj, indent: int = 0) -> str:
    """The plain listing of a result, for a command without a human view."""
    pad = "  " * indent
    if isinstance(obj, dict):
        lines = []
        for k, v in obj.items():
            if isinstance(v, (dict, list)) and v and not all(isinstance(e, (int, float)) for e in v):
                lines.append(f"{pad}{k}:")
                lines.append(_dump(v, indent + 1))
            else:
                lines.append(f"{pad}{k}: {json.dumps(v)}")
        return "\n".join(lines)
    if isinstance(obj, list):
        return "\n".join(f"{pad}- {json.dumps(v)}" for v in obj)
    return f"{pad}{obj}"


def _scene_or_none(args):
    """The scene of a one-scene command (its units and stated values), or None."""
    if not hasattr(args, "scene"):
        return None
    from levitron.runtime.cli.commands.common import scene_of
    try:
        return scene_of(args)
    except UserError:
        return None


def render(args, result) -> str:
    """The text printed for `result`: JSON with --json, else the command's human view."""
    if args.json:
        return json.dumps(result)
    view = getattr(args._module, "human", None)
    return view(result, _scene_or_none(args)) if view else _dump(result)


def _debug() -> bool:
    return os.environ.get("LEVITRON_DEBUG", "") not in ("", "0")


def one_line(text: str) -> str:
    """The first non-empty line of a message; a longer message is named as cut (the rest is shown
    with LEVITRON_DEBUG=1)."""
    lines = [ln.strip() for ln in str(text).splitlines() if ln.strip()]
    if not lines:
        return "(no message)"
    if len(lines) == 1:
        return lines[0]
    return f"{lines[0]} [{len(lines) - 1} more lines: set LEVITRON_DEBUG=1 to see them]"


def os_error_message(exc: OSError) -> str:
    """An OSError of a path the user gave (a scene, an output file, a folder, the cache) as one line."""
    why = exc.strerror or type(exc).__name__
    paths = " -> ".join(str(p) for p in (exc.filename, exc.filename2) if p is not None)
    if not paths:
        return f"{why}: {exc}"
    return f"{paths}: {why}"


def _scene_units(args):
    """The Units of the command's scene, or None where it has none or cannot be read."""
    if not getattr(args, "scene", None):
        return None
    from levitron.runtime.cli.commands.common import scene_of
    from levitron.runtime.ui.human import Units
    try:
        return Units.of_scene(scene_of(args))
    except Exception:           # noqa: BLE001  (the error being reported may be the scene's own)
        return None


def _report(args, exc: BaseException) -> int:
    """Print the one-line message of `exc` and return the exit code. A UserError's settings are
    worded as flags and its quantities shown in the scene's units (runtime/words.py)."""
    from levitron.scene.checks import SceneError
    from levitron.runtime.model.cbuild import CompileError
    prefix = f"levitron {args.command}"
    if isinstance(exc, (UserError, SceneError)):
        message = exc.words("cli", _scene_units(args)) if isinstance(exc, UserError) else str(exc)
        text, code = f"{prefix}: error: {one_line(message)}", EXIT_USER
    elif isinstance(exc, CompileError):
        output = str(exc).splitlines()[1:]          # the first line is the compiler's command
        detail = next((ln for ln in output if "error:" in ln), "")
        text, code = (f"{prefix}: error: the C compiler failed: {one_line(detail or str(exc))} "
                      "(LEVITRON_DEBUG=1 shows its full output)"), EXIT_USER
    elif isinstance(exc, MemoryError):
        text, code = (f"{prefix}: error: not enough memory for this request ({one_line(str(exc))}): "
                      "ask for less (fewer output samples, points or a shorter run)"), EXIT_USER
    elif isinstance(exc, OSError):
        text, code = f"{prefix}: error: {os_error_message(exc)}", EXIT_USER
    else:
        text, code = (f"{prefix}: internal error: {type(exc).__name__}: {one_line(str(exc))} "
                      "(set LEVITRON_DEBUG=1 for the traceback; please report it)"), EXIT_INTERNAL
    print(text, file=sys.stderr)
    return code


def _quiet_stdout() -> None:
    """After a closed pipe: point stdout at /dev/null, so that the interpreter's final flush
    raises nothing (the Python docs' recipe for SIGPIPE)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):   # an in-memory stdout (tests) has no descriptor
        pass
    finally:
        os.close(devnull)


def _emit(text: str, styled: bool = False) -> int:
    """Write the result to stdout (through rich on a terminal: numbers highlighted, the answer in
    bold); a reader that went away (`| head -1`) is not an error."""
    try:
        if styled and sys.stdout.isatty():
            from rich.console import Console
            from rich.highlighter import ReprHighlighter
            from rich.text import Text
            head, _, rest = text.partition("\n")
            body = ReprHighlighter()(Text(head, style="bold"))
            if rest:
                body.append("\n").append_text(ReprHighlighter()(Text(rest)))
            Console(soft_wrap=True).print(body)
        else:
            sys.stdout.write(text + "\n")
        sys.stdout.flush()
    except BrokenPipeError:
        _quiet_stdout()
    return 0


def _with_provenance(args, result):
    """Every JSON object carries where it came from (runtime/ui/provenance.py); a command that made
    its own block (the report, which shows it) keeps it."""
    if isinstance(result, dict) and "provenance" not in result:
        scene = _scene_or_none(args)
        result["provenance"] = provenance.block(args._argv, scene, getattr(args, "set", ()))
    return result


def _refuse_empty(argv: list[str]) -> None:
    """An empty value (`--out ''`, `--out=`, a scene '') is refused: it never silently means the
    default or the current folder."""
    for i, token in enumerate(argv[1:], start=1):
        flag = token[:-1] if token.startswith("--") and token.endswith("=") else None
        if token == "":
            flag = argv[i - 1] if argv[i - 1].startswith("-") else None
            if flag is None:
                raise UserError(f"an empty argument '' after `levitron {argv[0]}`: give the scene (a name "
                                "`levitron scenes` lists, or a .toml path)")
        if flag is not None:
            raise UserError(f"{flag} '': an empty value; give one (see `levitron {argv[0]} --help`)")


def _one_temperature(args) -> None:
    """--temperature and --set temperature=... name one number twice: refused, not resolved."""
    for text in args.set:
        if text.split("=", 1)[0].strip() == "temperature":
            raise UserError(f"--temperature {args.temperature:g} and --set '{text}' both set the temperature: "
                            "pass one of them")


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv == ["--version"]:       # without the command modules (numpy, casadi): ~0.1 s, not ~1 s
        return _emit(f"levitron {version()}")
    if not argv or argv[0] in ("-h", "--help") or argv[0] not in COMMANDS and not argv[0].startswith("-"):
        # the overview, no command module imported: the help, or a misspelt command's one line
        build_parser(overview=True).parse_args(argv)
    args = build_parser(argv[0] if argv else None).parse_args(argv)
    try:
        _refuse_empty(argv)
        if getattr(args, "temperature", None) is not None:     # one more --set, resolved by the scene
            _one_temperature(args)
            args.set = [*args.set, f"temperature={args.temperature!r}"]
        _typed_inputs(args)
    except UserError as exc:
        return _report(args, exc)
    args._argv = argv
    from levitron.scene.checks import SceneError
    from levitron.runtime.model.cbuild import resolve_cache_env
    from levitron.runtime.model import processes
    resolve_cache_env()           # a relative LEVITRON_CACHE: from the user's folder, once
    if args.json or args.quiet:
        progress.disable()
    else:
        progress.enable()
    # SIGINT and SIGTERM: one KeyboardInterrupt; the finally blocks remove their temporaries and
    # end the worker processes, and the command exits 128 + the signal's number
    with processes.stop_on_signals():
        try:
            with progress.task(f"levitron {args.command}"):
                result = _clean(_with_provenance(args, args._run(args)))
                if args.json and isinstance(result, dict):     # the API answer's success (cli/success.py)
                    result["success"] = success_of(args.command, result)
                units = _scene_units(args)
                # the JSON's quantities in the scene's units; a plain view shows them in the human ones
                # (ui/human.py restate: cm, g, spans), so it reads the quantity markers themselves
                result = speak(result, "cli", units) if args.json else result
            text = words(render(args, result), "cli", units)     # what the plain view left: the scene's units
        except KeyboardInterrupt:
            processes.stopped()
            print(f"levitron {args.command}: interrupted", file=sys.stderr)
            return processes.exit_code(EXIT_INTERRUPTED)
        except BrokenPipeError:
            _quiet_stdout()
            return 0
        except Exception as exc:    # every failure is one line; the traceback only on request
            processes.stopped()
            if processes.stop_signal() is not None and not _debug():    # an error the stop caused
                print(f"levitron {args.command}: interrupted", file=sys.stderr)    # (CasADi's SystemError)
                return processes.exit_code(EXIT_INTERRUPTED)
            if _debug() and not isinstance(exc, (UserError, SceneError)):
                raise
            return _report(args, exc)
    return _emit(text, styled=not args.json)


if __name__ == "__main__":
    sys.exit(main())
