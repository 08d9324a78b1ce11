"""Where an answer came from: the `provenance` block of every JSON object (and of the report).

    {"package": "levitron", "version": "0.4.0", "command": "levitron stability thesis --set ...",
     "time": "2026-12-01T20:40:00+00:00", "python": "3.11.7",
     "scene": "thesis", "scene_path": "/.../scenes/thesis.toml", "overrides": ["top.mass=0.03"],
     "scene_hash": sha256 of the resolved scene (numbers and overrides included),
     "input_hash": the generated model's (scene/inputs.py: structure, derive sources, tools)}

Run the command again on the same version, from the scene at scene_path, and the numbers repeat:
scene_hash says whether the scene (with its overrides) is still the one the answer was for.
"""
from __future__ import annotations

import datetime
import functools
import platform
import shlex
from pathlib import Path


@functools.lru_cache(maxsize=1)
def version() -> str:
    """The installed package's version, else the one in this source tree's pyproject.toml (read
    once per process: the parser and the provenance block both ask)."""
    from importlib import metadata
    try:
        return metadata.version("levitron")
    except metadata.PackageNotFoundError:
        import tomllib
        pyproject = Path(__file__).resolve().parents[2] / "pyproject.toml"
        return tomllib.loads(pyproject.read_text())["project"]["version"]


def command_line(argv) -> str:
    """The command as a shell would take it again."""
    return "levitron " + shlex.join(str(a) for a in argv)


def block(argv, scene=None, overrides=(), call: str | None = None) -> dict:
    """The provenance of one answer: `argv` the command's arguments (or `call`, an API call's
    text), `scene` the loaded scene.load.Scene (None for a command of several scenes)."""
    out = {"package": "levitron", "version": version(),
           "command": call if call is not None else command_line(argv),
           "time": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "python": platform.python_version()}
    if scene is not None:
        from levitron.scene.inputs import input_hash
        out.update(scene=scene.name,
                   scene_path=None if scene.path is None else str(Path(scene.path).resolve()),
                   overrides=list(overrides), scene_hash=scene.scene_hash(),
                   input_hash=input_hash(scene.data))
    return out
