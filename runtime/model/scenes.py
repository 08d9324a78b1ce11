"""Scenes for the runtime: derive/scene.py's loader with its SceneError as the runtime's one-line
UserError, the one way the command line and the public API load a scene."""
from __future__ import annotations

from levitron.derive.scene import Scene, SceneError
from levitron.derive.scene import load_scene as _load

from levitron.runtime.errors import UserError


def load_scene(name_or_path, overrides=()) -> Scene:
    """A scene by name or path, with --set overrides; SceneError becomes a UserError."""
    try:
        return _load(name_or_path, list(overrides))
    except SceneError as exc:
        raise UserError(str(exc)) from None
