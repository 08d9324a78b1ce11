"""The scene language: what a scene file may say and what it means, in pure Python (no sympy).

`levitron.scene` reads a TOML scene, applies `--set` overrides and validates it into a `Scene`
with SI parameters (load.py; its keys keys.py, the override language overrides.py, the shared
validators and `SceneError` checks.py); the plate registry's scene side, one module per kind
(plates/: keys, resolver, structural decisions, docs/scenes.md); the input hash of a generated
model (inputs.py) and its files' digests (digest.py); where scenes/ and generated/ are (paths.py);
MU0 (constants.py); the kill tests' fault points (faults.py). derive/ (sympy) and runtime/ (numpy,
casadi, C) both stand on it; it imports neither (tests/house/test_layers.py).
"""
