"""`levitron scenes`: the scenes that ship with the package (scene/paths.py SCENES_DIR, inside the
package in a wheel): their names, plate kinds, descriptions and units."""
from __future__ import annotations

from levitron.scene.paths import SCENES_DIR

from levitron.runtime.model.scenes import load_scene
from levitron.runtime.ui.human import Units, lines

NAME = "scenes"
HELP = "the scenes that ship with levitron: name, plate kind, description, units (SI or dimensionless)"
EXAMPLE = "levitron scenes --json"
TAKES_SCENE = False       # no SCENE, --set or --temperature (runtime/cli/main.py)


def add_arguments(parser) -> None:
    pass


def _row(path) -> dict:
    scene = load_scene(path)
    description = str(scene.data.get("description") or "").strip()
    return {"name": path.stem, "plate": scene.plate_kind,
            "description": description.splitlines()[0] if description else None,
            "units": "SI" if Units.of_scene(scene).si else "dimensionless", "file": str(path)}


def run(args) -> dict:
    return {"folder": str(SCENES_DIR), "scenes": [_row(p) for p in sorted(SCENES_DIR.glob("*.toml"))]}


def human(r: dict, scene=None) -> str:
    """One line a scene: its name (what a command takes as SCENE), plate kind, units, description."""
    rows = r["scenes"]
    width = max((len(s["name"]) for s in rows), default=0)
    kinds = max((len(s["plate"]) for s in rows), default=0)
    return lines(f"{len(rows)} scenes (give one by name as SCENE, e.g. `levitron info thesis`, or a .toml "
                 "path of your own; `levitron keys` lists the keys a scene file takes):",
                 *[f"  {s['name']:<{width}}  {s['plate']:<{kinds}}  {s['units']:<13}  {s['description'] or ''}".rstrip()
                   for s in rows])
