"""Load a generated model: compile and cache its C, load its CasADi functions (no sympy here).

    model = load_model(scene)        # derives first (in a subprocess) if generated/ is missing or stale
    part = model.part("full")        # "reduced" | "full"
    part.rhs(x), part.energy(x), part.jac(x)          # backend="c" (default) or "casadi"

The C library is model.c compiled together with the hand-written runtime/csrc/*.c (integrators),
cached by content hash (runtime/cbuild.py).
"""
from __future__ import annotations

import ctypes
import json
import os
import shutil
import subprocess
import sys
import tempfile
from functools import cached_property
from pathlib import Path

import numpy as np

from derive.inputs import input_hash
from derive.scene import SCENES_DIR, Scene

from .cbuild import cache_dir, compile_shared
from .errors import UserError

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
CSRC = Path(__file__).resolve().parent / "csrc"

_DOUBLE_P = ctypes.POINTER(ctypes.c_double)
LEV_FN = ctypes.CFUNCTYPE(None, _DOUBLE_P, _DOUBLE_P, _DOUBLE_P)

NEEDS_OF_PART = {"reduced": "reduced", "full": "full"}


class MissingPart(UserError):
    """The scene's model lacks a part that a command needs."""


def _ptr(a: np.ndarray):
    return a.ctypes.data_as(_DOUBLE_P)


class CFunction:
    """The one ctypes call path: a generated (or runtime/csrc test) C function
    `void f(const double *in, const double *p, double *out)` bound to preallocated buffers of the
    sizes the manifest states (the marshalling of a fresh call costs more than the function).

        f = CFunction(fn, n_in, n_out, p);  y = f(x)          # a copy of the output
    """

    def __init__(self, fn, n_in: int, n_out: int, p: np.ndarray):
        fn.argtypes = [_DOUBLE_P, _DOUBLE_P, _DOUBLE_P]
        fn.restype = None
        self._fn = fn
        self.n_in, self.n_out = int(n_in), int(n_out)
        self._in = np.zeros(self.n_in)
        self._out = np.zeros(self.n_out)
        self._p = np.array(p, dtype=float).reshape(-1)
        self._args = tuple(_ptr(a) for a in (self._in, self._p, self._out))

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float).reshape(-1)
        if x.size != self.n_in:
            raise ValueError(f"expected {self.n_in} inputs, got {x.size}")
        self._in[:] = x
        self._fn(*self._args)
        return self._out.copy()


def _own_scene(scene: Scene) -> bool:
    return scene.path is not None and Path(scene.path).resolve().parent == SCENES_DIR.resolve()


def generated_dir(scene: Scene, overrides=()) -> Path:
    """Where the scene's model lives: generated/<name>/ when that is current for the scene (a scene
    of scenes/, also with --set overrides of numbers, which are runtime parameters), else a folder
    in the cache keyed by the input hash. The runtime never writes into generated/: only
    `make derive` does."""
    ihash = input_hash(scene.data)
    if _own_scene(scene) and _manifest_hash(GENERATED / scene.name) == ihash:
        return GENERATED / scene.name
    return cache_dir() / "derived" / f"{scene.name}-{ihash[:16]}"


def _manifest_hash(folder: Path) -> str | None:
    try:
        return json.loads((folder / "manifest.json").read_text()).get("input_hash")
    except (FileNotFoundError, NotADirectoryError, json.JSONDecodeError):
        return None


def ensure_generated(scene: Scene, overrides=()) -> Path:
    """The scene's generated folder; derived first (python -m derive, in a subprocess: the runtime
    does not import sympy) into the cache when no current one exists. The new folder appears by one
    rename, so concurrent processes (scan workers) never see a half-written model."""
    out = generated_dir(scene, overrides)
    ihash = input_hash(scene.data)
    if _manifest_hash(out) == ihash:
        return out
    if _own_scene(scene) and (GENERATED / scene.name).exists() and not overrides:
        print(f"levitron: generated/{scene.name} is stale (the scene or derive/ changed): using a "
              "fresh derivation in the cache; run `make derive` to update generated/", file=sys.stderr)
    print(f"levitron: deriving the model of scene '{scene.name}' ...", file=sys.stderr)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{scene.name}-", dir=out.parent))
    try:
        cmd = [sys.executable, "-m", "derive", str(scene.path), "--out", str(tmp), "--force"]
        for o in overrides:
            cmd += ["--set", o]
        res = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=False)
        if res.returncode != 0:
            raise UserError(f"derive failed for scene '{scene.name}': {res.stderr.strip()}")
        try:
            os.replace(tmp / scene.name, out)
        except OSError:
            if _manifest_hash(out) != ihash:   # not another process's identical result: a real error
                raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


class Part:
    """One part ("reduced" or "full") of a loaded model."""

    def __init__(self, model: "Model", name: str):
        self.model = model
        self.name = name
        info = model.manifest["parts"][name]
        self.states: list[str] = list(info["states"])
        self.params: list[str] = list(model.manifest["parameters"])
        self.nx = len(self.states)

    @property
    def p(self) -> np.ndarray:
        return self.model.p

    def has(self, kind: str) -> bool:
        return f"{self.name}_{kind}" in self.model.manifest["functions"]

    def c_function(self, kind: str):
        """The ctypes function pointer of `<part>_<kind>` (signature: in, p, out)."""
        return self.model.c_function(f"{self.name}_{kind}")

    def casadi(self, kind: str):
        return self.model.casadi(f"{self.name}_{kind}")

    def _call(self, kind, x, p, backend):
        return self.model.call(f"{self.name}_{kind}", x, p, backend)

    def rhs(self, x, p=None, backend: str = "c") -> np.ndarray:
        """d state / dt (thesis eqs. 2.3.10-2.3.16, or the reduced 4-D system after eq. 3.2.12)."""
        return self._call("rhs", x, p, backend)

    def energy(self, x, p=None, backend: str = "c") -> float:
        """The Hamiltonian (thesis eq. 2.3.9 / 3.2.12)."""
        return float(self._call("energy", x, p, backend)[0])

    def jac(self, x, p=None, backend: str = "c") -> np.ndarray:
        if not self.has("jac"):
            raise MissingPart(f"scene '{self.model.scene.name}' has no Jacobian of the {self.name} "
                              f"model: add \"linear\" to model.needs")
        return self._call("jac", x, p, backend).reshape(self.nx, self.nx)

    def index(self, state_name: str) -> int:
        return self.states.index(state_name)


class Model:
    """A generated model with its scene's parameter values."""

    def __init__(self, scene: Scene, folder: Path):
        self.scene = scene
        self.folder = Path(folder)
        self.manifest = json.loads((self.folder / "manifest.json").read_text())
        names = self.manifest["parameters"]
        missing = [n for n in names if n not in scene.params]
        if missing:
            raise UserError(f"scene '{scene.name}' gives no value for parameter {missing[0]}: "
                            "re-derive the model (make derive)")
        self.p = np.array([scene.params[n] for n in names], dtype=float)
        self._casadi = {}
        self._parts = {}
        self._cfuncs = {}

    # ---- parts
    @property
    def parts(self) -> list[str]:
        return list(self.manifest["parts"])

    def part(self, name: str) -> Part:
        if name not in self.manifest["parts"]:
            raise MissingPart(f"scene '{self.scene.name}' has no {name} model (model.needs = "
                              f"{self.scene.needs}): add \"{NEEDS_OF_PART.get(name, name)}\" to "
                              "model.needs in the scene")
        if name not in self._parts:
            self._parts[name] = Part(self, name)
        return self._parts[name]

    def param(self, name: str) -> float:
        return float(self.p[self.manifest["parameters"].index(name)])

    # ---- C backend
    @cached_property
    def library_path(self) -> Path:
        sources = [self.folder / "model.c"] + sorted(CSRC.glob("*.c"))
        return compile_shared(sources, include_dirs=(self.folder, CSRC))

    @cached_property
    def lib(self) -> ctypes.CDLL:
        return ctypes.CDLL(str(self.library_path))

    def c_function(self, name: str):
        fn = self._cfuncs.get(name)
        if fn is None:
            if name not in self.manifest["functions"]:
                raise MissingPart(f"scene '{self.scene.name}' has no generated function {name}")
            fn = getattr(self.lib, name)
            fn.argtypes = [_DOUBLE_P, _DOUBLE_P, _DOUBLE_P]
            fn.restype = None
            self._cfuncs[name] = fn
        return fn

    def fast(self, name: str, p: np.ndarray | None = None) -> CFunction:
        """The generated C function `name` bound to parameters p (default the scene's) with
        preallocated buffers: for hot loops (root searches, Jacobian sweeps)."""
        info = self.manifest["functions"].get(name)
        if info is None:
            raise MissingPart(f"scene '{self.scene.name}' has no generated function {name}")
        p = self.p if p is None else np.asarray(p, dtype=float)
        if p.size != self.p.size:
            raise ValueError(f"{name}: expected {self.p.size} parameters, got {p.size}")
        return CFunction(self.c_function(name), info["n_in"], info["n_out"], p)

    # ---- CasADi backend
    def casadi(self, name: str):
        import casadi as ca
        if name not in self._casadi:
            info = self.manifest["functions"].get(name)
            if info is None:
                raise MissingPart(f"scene '{self.scene.name}' has no generated function {name}")
            self._casadi[name] = ca.Function.load(str(self.folder / info["casadi"]))
        return self._casadi[name]

    # ---- evaluation
    def call(self, name: str, x, p=None, backend: str = "c") -> np.ndarray:
        info = self.manifest["functions"].get(name)
        if info is None:
            raise MissingPart(f"scene '{self.scene.name}' has no generated function {name}")
        x = np.ascontiguousarray(x, dtype=float).reshape(-1)
        p = self.p if p is None else np.ascontiguousarray(p, dtype=float)
        if x.size != info["n_in"] or p.size != self.p.size:
            raise ValueError(f"{name}: expected {info['n_in']} inputs and "
                             f"{len(self.manifest['parameters'])} parameters, got {x.size}, {p.size}")
        if backend == "c":
            return self.fast(name, p)(x)
        if backend == "casadi":
            return np.asarray(self.casadi(name)(x, p), dtype=float).reshape(-1)
        raise UserError(f"unknown backend {backend!r}: use 'c' or 'casadi'")

    def onaxis(self, z, p=None, backend: str = "c") -> np.ndarray:
        """[Phi_0, ..., Phi_K](z) of the plate (thesis eq. 2.2.6 and eqs. 2.2.12-2.2.14)."""
        return self.call("onaxis", [float(z)], p, backend)

    def field(self, xyz, p=None, backend: str = "c") -> np.ndarray:
        """B(x, y, z) from the model's expansion (thesis eq. 2.2.7)."""
        return self.call("field", xyz, p, backend)


def load_model(scene: Scene, overrides=()) -> Model:
    """The loaded model of a scene (derived first if needed). `overrides` are the --set strings."""
    return Model(scene, ensure_generated(scene, overrides))
