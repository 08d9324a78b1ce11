"""Helpers shared by the command modules: load the scene and the model from parsed arguments."""
from __future__ import annotations

from derive.scene import Scene, SceneError, load_scene

from ..errors import UserError
from ..model import Model, load_model


def load(name_or_path, overrides=()) -> Scene:
    """A scene by name or path, with --set overrides; SceneError becomes a UserError."""
    try:
        return load_scene(name_or_path, list(overrides))
    except SceneError as exc:
        raise UserError(str(exc)) from None


def scene_of(args) -> Scene:
    return load(args.scene, args.set)


def model_of(args) -> Model:
    return load_model(scene_of(args), args.set)
