"""Helpers shared by the command modules: load the scene and the model from parsed arguments."""
from __future__ import annotations

from derive.scene import Scene, SceneError, load_scene

from ..errors import UserError
from ..model import Model, load_model


def scene_of(args) -> Scene:
    try:
        return load_scene(args.scene, args.set)
    except SceneError as exc:
        raise UserError(str(exc)) from None


def model_of(args) -> Model:
    return load_model(scene_of(args), args.set)
