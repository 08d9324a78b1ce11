"""Scenes for the runtime: scene/load.py's loader with its SceneError as the runtime's one-line
UserError, the one way the command line and the public API load a scene."""
from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

from levitron.scene.load import Scene, SceneError, find_scene_file
from levitron.scene.load import load_scene as _load

from levitron.runtime.errors import UserError


def load_scene(name_or_path, overrides=()) -> Scene:
    """A scene by name or path, with --set overrides; SceneError becomes a UserError."""
    try:
        return _load(name_or_path, list(overrides))
    except SceneError as exc:
        raise UserError(_reason(name_or_path, exc)) from None


class SceneRef(NamedTuple):
    """The recipe that rebuilds a model in another process (scan and launch workers, a design's
    variants): the scene's file as an absolute path (or a name) and its --set strings."""
    scene: str
    overrides: tuple[str, ...] = ()

    def with_overrides(self, more) -> SceneRef:
        """The recipe of a variant: these overrides and then `more` (later ones win)."""
        return SceneRef(self.scene, (*self.overrides, *more))


def ref_of(scene: Scene) -> SceneRef:
    """The recipe of a loaded scene: its file's absolute path (else its name) and the overrides
    load_scene applied."""
    where = str(Path(scene.path).resolve()) if scene.path is not None else scene.name
    return SceneRef(where, tuple(scene.overrides))


BOM = b"\xef\xbb\xbf"


def _reason(name_or_path, exc: SceneError) -> str:
    """The scene reader's message, or for a file that TOML refuses at its first character because it
    starts with a UTF-8 byte-order mark, that reason (the reader's says only "at line 1, column 1")."""
    text = str(exc)
    if "not valid TOML" not in text:
        return text
    try:
        path = find_scene_file(name_or_path)
        with open(path, "rb") as fh:
            head = fh.read(len(BOM))
    except (SceneError, OSError):
        return text
    if head != BOM:
        return text
    return (f"{path}: starts with a byte-order mark (U+FEFF, which some editors write before UTF-8 "
            "text) and TOML allows none: save the file as UTF-8 without a BOM")
