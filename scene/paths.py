"""Where things live in the repository, defined once (pure Python: the runtime imports it too).

Committed models: generated/<name>/ is written only by `make derive` (python -m levitron.derive without
--out), and only for a scene of scenes/ whose file is scenes/<name>.toml, without --set overrides.
"""
from __future__ import annotations

from pathlib import Path

# resolve(): imported as levitron.scene.paths, __file__ is levitron/scene/paths.py, through the link to scene/
ROOT = Path(__file__).resolve().parent.parent      # the checkout, or levitron/ in a wheel
SCENES_DIR = ROOT / "scenes"
GENERATED = ROOT / "generated"
DERIVE_DIR = ROOT / "derive"      # its sources are the input hash's (scene/inputs.py)


def is_committed_scene(name: str, path: Path | str | None) -> bool:
    """Whether the scene read from `path` under the name `name` is one of scenes/ (its model is
    committed as generated/<name>/): the file is scenes/<name>.toml."""
    if path is None:
        return False
    path = Path(path).resolve()
    return path.parent == SCENES_DIR.resolve() and path.name == f"{name}.toml"
