"""Write a scene's data back as TOML (`optimize --write-scene FILE`): a small writer for what
scene/load.py reads (top-level keys, sections, sub-tables, arrays of tables, numbers, strings,
booleans, lists of strings), checked by re-reading; written atomically (nothing half-written).
The scene carries its `name` (the file's stem); a designed key is written as the shortest decimal
within RESOLUTION of the optimum (`shortest`: 0.0519 g, not 0.018999999999999996), finer than any
design's own resolution (the launch-odds grid's last step is ~1e-3 of its box, IPOPT's optimum is
flat to second order)."""
from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

from levitron.scene.load import Scene, SceneError, validate

from levitron.runtime.errors import UserError

RESOLUTION = 1e-6        # relative: a designed value is written to within this of the optimum


def shortest(v: float, rel: float = RESOLUTION) -> float:
    """The float of the shortest decimal within rel |v| of v (v itself where none is shorter)."""
    v = float(v)
    for digits in range(1, 18):
        w = float(f"{v:.{digits}g}")
        if abs(w - v) <= rel * abs(v):
            return w
    return v


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)            # a JSON string is a TOML basic string
    if isinstance(v, list) and all(not isinstance(x, dict) for x in v):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise UserError(f"cannot write {v!r} as a TOML value")


def _table(lines: list[str], name: str, table: dict) -> None:
    scalars = {k: v for k, v in table.items() if not isinstance(v, dict)
               and not (isinstance(v, list) and v and all(isinstance(x, dict) for x in v))}
    lines.append(f"\n[{name}]")
    lines += [f"{k} = {_value(v)}" for k, v in scalars.items()]
    for k, v in table.items():
        if isinstance(v, dict):
            _table(lines, f"{name}.{k}", v)
        elif k not in scalars:
            for part in v:
                lines.append(f"\n[[{name}.{k}]]")
                lines += [f"{pk} = {_value(pv)}" for pk, pv in part.items()]


def scene_toml(scene: Scene, comment: str = "", name: str | None = None) -> str:
    data = scene.data
    lines = [f"# {line}" for line in comment.splitlines()]
    # the scene's `name`: the file's (scene/load.py load_scene names a scene without one after it)
    lines += [f"name = {_value(name)}"] if name else []
    lines += [f"{k} = {_value(v)}" for k, v in data.items() if not isinstance(v, dict) and k != "name"]
    for k, v in data.items():
        if isinstance(v, dict):
            _table(lines, k, v)
    return "\n".join(lines) + "\n"


def check_target(path: str | Path) -> Path:
    """A path a scene can be written to (its folder exists, it is not a folder); UserError if not."""
    p = Path(path)
    if p.is_dir() or not p.parent.is_dir() or p.suffix != ".toml":
        raise UserError(f"«write_scene» {path}: give a .toml file in an existing folder")
    if not re.fullmatch(r"[A-Za-z0-9_-]+", p.stem):
        raise UserError(f"«write_scene» {path}: the file name names the scene; use letters, digits, "
                        "'-' and '_' only")
    return p


def write_scene(scene: Scene, path: str | Path, comment: str = "") -> Path:
    """Write the scene to path atomically; the text is re-read and must give the same data."""
    from levitron.runtime.ui.atomic import output
    p = check_target(path)
    with output(p, "«write_scene»") as tmp:     # mode 0666 less the umask, as any file written
        text = scene_toml(scene, comment, p.stem)
        tmp.write_text(text, encoding="utf-8")
        try:                  # read back as load_scene reads the file, named after the target
            data = tomllib.loads(tmp.read_text(encoding="utf-8"))
            data.setdefault("name", p.stem)
            again = validate(data, p)
        except (SceneError, tomllib.TOMLDecodeError) as exc:
            raise UserError(f"«write_scene» {path}: the written scene does not read back ({exc})") from None
        if again.params != scene.params:
            raise UserError(f"«write_scene» {path}: the written scene reads back different numbers")
    return p


def write_design(scene: Scene, optimum: dict, objective: str, path: str | Path) -> str:
    """A design's `write_scene` action: the scene at the optimum (each key's shortest decimal within
    RESOLUTION) written to path, its first line naming the command and the objective."""
    from levitron.runtime.design.scene_keys import with_values
    from levitron.runtime.words import render
    note = (f"levitron optimize {scene.name} «maximize={objective}»: "
            + ", ".join(f"{k} = {v:.6g}" for k, v in optimum.items()))
    at = with_values(scene, {k: shortest(v) for k, v in optimum.items()})
    return str(write_scene(at, path, render(note, "cli")))
