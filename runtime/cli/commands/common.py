"""Helpers shared by the command modules: load the scene and the model from parsed arguments."""
from __future__ import annotations

from levitron.scene.load import Scene

from levitron.runtime.model.load import Model, load_model
from levitron.runtime.model.scenes import load_scene as load


def scene_of(args) -> Scene:
    return load(args.scene, args.set)


def model_of(args) -> Model:
    return load_model(scene_of(args))
