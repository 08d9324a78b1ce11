"""`levitron report SCENE --out FILE.html`: one self-contained page about a scene (runtime/report/page.py)."""
from __future__ import annotations

from pathlib import Path

from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import Units, lines, sig
from levitron.runtime.report.page import build
from levitron.runtime.cli.commands.common import model_of, scene_of

NAME = "report"
HELP = ("one self-contained HTML page: the scene, equilibria and stable band, spin interval, a small "
        "stability map and a typical launch (figures embedded)")
EXAMPLE = "levitron report thesis_stable --out out/thesis_stable.html"


def add_arguments(parser) -> None:
    parser.add_argument("--out", required=True, metavar="FILE.html", help="the page to write (.html)")


def _check_out(path: Path) -> Path:
    if path.is_dir() or not path.name:          # a folder ('.', '/', out/) before its suffix
        raise UserError(f"--out {path} is a folder: give a file name in it, e.g. --out {path / 'report.html'}")
    if path.suffix.lower() not in (".html", ".htm"):
        raise UserError(f"--out {path}: the file name must end in .html, e.g. --out "
                        f"{path.with_suffix('.html')}")
    return path


def _write(path: Path, text: str) -> None:
    """Atomically: a temporary file beside the target, renamed into place (runtime/ui/atomic.py)."""
    from levitron.runtime.ui.atomic import write_text
    write_text(path, text, "--out", mkdir=True)


def run(args) -> dict:
    out = _check_out(Path(args.out))
    scene = scene_of(args)
    model = model_of(args)
    from levitron.runtime.ui.provenance import block
    page, facts = build(model, block(getattr(args, "_argv", ["report", args.scene]),
                                                    scene, args.set))
    _write(out, page)
    facts["out"] = str(out)
    facts["bytes"] = len(page.encode("utf-8"))
    return facts


def human(r: dict, scene=None) -> str:
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    iv = r.get("spin_interval")
    return lines(f"report: {r['out']} ({sig(r['bytes'] / 1024, 3)} kB, one self-contained page)",
                 f"spin interval {u.rate_span(*iv)} at z_s = {u.length(r['z_s'])}" if iv
                 else "no stable spin interval", r.get("not_drawn"), u.note)
