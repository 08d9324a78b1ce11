"""Load a generated model: verify it, compile and cache its C, load its CasADi functions (no sympy).

    model = load_model(scene)        # derives first (in a subprocess) if generated/ is missing or stale
    part = model.part("full")        # "reduced" | "full"
    part.rhs(x), part.energy(x), part.jac(x)          # backend="c" (default) or "casadi"

Nothing is used unverified: the manifest is typed and checked, with the sha256 of itself and of
every file (runtime/model/manifest.py); the compiled library's own table must agree with the manifest
before any call (runtime/model/table.py); a damaged cached model is derived again, once, and a
damaged generated/ is an error saying `make derive` (where a model lives and how it comes to be
there: runtime/model/locate.py). The C library is model.c compiled together
with the hand-written runtime/csrc/*.c (integrators), cached by content hash (runtime/model/cbuild.py).
"""
from __future__ import annotations

import ctypes
import sys
import threading
from functools import cached_property
from pathlib import Path

import numpy as np

from levitron.scene.load import Scene

from levitron.runtime.model.cbuild import compile_shared, discard
from levitron.runtime.errors import UserError
from levitron.runtime.model.manifest import ArtefactError, FunctionInfo, Manifest, read_manifest
from levitron.runtime.model.table import disagreement, read_table
from levitron.runtime.model.locate import locate, make_derive_fix

CSRC = Path(__file__).resolve().parent.parent / "csrc"

_DOUBLE_P = ctypes.POINTER(ctypes.c_double)
_VOID3 = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)

NEEDS_OF_PART = {"reduced": "reduced", "full": "full"}


class MissingPart(UserError):
    """The scene's model lacks a part that a command needs."""


class CFunction:
    """The one ctypes call path: a generated (or runtime/csrc test) C function
    `void f(const double *in, const double *p, double *out)` bound to preallocated buffers of the
    sizes the manifest states, checked against the library's own table (Model.lib) (the
    marshalling of a fresh call costs more than the function).

        f = CFunction(fn, n_in, n_out, p);  y = f(x)          # a copy of the output
    """

    def __init__(self, fn, n_in: int, n_out: int, p: np.ndarray):
        # its own prototype over the function's address, taking plain int addresses: a third of
        # the cost of a call through pointer argtypes (the equilibrium survey makes ~800 a search)
        self._fn = _VOID3(ctypes.cast(fn, ctypes.c_void_p).value)
        self.n_in, self.n_out = int(n_in), int(n_out)
        self._in = np.zeros(self.n_in)
        self._out = np.zeros(self.n_out)
        self._p = np.array(p, dtype=float).reshape(-1)
        self._args = tuple(a.ctypes.data for a in (self._in, self._p, self._out))

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float).reshape(-1)
        if x.size != self.n_in:
            raise ValueError(f"expected {self.n_in} inputs, got {x.size}")
        self._in[:] = x
        self._fn(*self._args)
        return self._out.copy()

    def bind(self, p) -> None:
        """Give the function parameters p (copied into the buffer C reads)."""
        p = np.asarray(p, dtype=float).reshape(-1)
        if p.size != self._p.size:
            raise ValueError(f"expected {self._p.size} parameters, got {p.size}")
        self._p[:] = p

    def at(self, z: float) -> np.ndarray:
        """f([z]) for a function of one input (the on-axis functions of a height), without the
        array conversion."""
        if self.n_in != 1:
            raise ValueError(f"at(z) is for a function of one input; this one takes {self.n_in}")
        self._in[0] = z
        self._fn(*self._args)
        return self._out.copy()


class Part:
    """One part ("reduced" or "full") of a loaded model."""

    def __init__(self, model: Model, name: str):
        self.model = model
        self.name = name
        self.states: list[str] = list(model.manifest.parts[name].states)
        self.params: list[str] = model.param_names
        self.nx = len(self.states)

    @property
    def p(self) -> np.ndarray:
        return self.model.p

    def has(self, kind: str) -> bool:
        return self.model.has_function(f"{self.name}_{kind}")

    def c_function(self, kind: str):
        """The ctypes function pointer of `<part>_<kind>` (signature: in, p, out)."""
        return self.model.c_function(f"{self.name}_{kind}")

    def casadi(self, kind: str):
        return self.model.casadi(f"{self.name}_{kind}")

    def taylor_function(self):
        """The ctypes pointer of `<part>_taylor` (derive/emit/taylor.py), or None if it has none."""
        return self.model.taylor_function(self.name)

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
    """A verified generated model with its scene's parameter values.

    `manifest` is the typed Manifest (runtime/model/manifest.py); `fix` says what to do when a file of
    the folder turns out damaged (default: `make derive`)."""

    def __init__(self, scene: Scene, folder: Path, manifest: Manifest | None = None,
                 fix: str | None = None):
        self.scene = scene
        self.folder = Path(folder)
        self.fix = fix or make_derive_fix(self.folder.name)
        self.manifest = manifest if manifest is not None else read_manifest(self.folder, self.fix)
        names = self.manifest.parameters
        missing = [n for n in names if n not in scene.params]
        if missing:
            raise UserError(f"scene '{scene.name}' gives no value for parameter {missing[0]}: "
                            "re-derive the model (make derive)")
        self.p = np.array([scene.params[n] for n in names], dtype=float)
        self._casadi = {}
        self._parts = {}
        self._cfuncs = {}
        self._bound = threading.local()   # call's CFunctions, per thread (ctypes drops the GIL)
        self._rows_addr = {}

    @property
    def ref(self):
        """The recipe that rebuilds this model in another process (runtime/model/scenes.py SceneRef:
        the scene's file and its overrides); load_model(load_scene(*model.ref)) is the same model."""
        from levitron.runtime.model.scenes import ref_of
        return ref_of(self.scene)

    # ---- parameters
    @property
    def param_names(self) -> list[str]:
        """The parameter names in the order of the vector p."""
        return list(self.manifest.parameters)

    def _index(self, name: str) -> int:
        try:
            return self.manifest.parameters.index(name)
        except ValueError:
            raise UserError(f"unknown parameter {name!r}: the model's parameters are "
                            f"{', '.join(self.manifest.parameters)}") from None

    def param(self, name: str) -> float:
        """The scene's value of one parameter (UserError naming the valid ones if unknown)."""
        return float(self.p[self._index(name)])

    def pvals(self, p=None) -> dict[str, float]:
        """name -> value of the parameter vector p (default the scene's)."""
        p = self.p if p is None else np.asarray(p, dtype=float).reshape(-1)
        if p.size != len(self.manifest.parameters):
            raise ValueError(f"expected {len(self.manifest.parameters)} parameters, got {p.size}")
        return {n: float(v) for n, v in zip(self.manifest.parameters, p)}

    def with_params(self, overrides: dict, p=None) -> np.ndarray:
        """A copy of p (default the scene's) with the named parameters replaced."""
        out = np.array(self.p if p is None else p, dtype=float).reshape(-1)
        if out.size != len(self.manifest.parameters):
            raise ValueError(f"expected {len(self.manifest.parameters)} parameters, got {out.size}")
        for name, value in overrides.items():
            out[self._index(name)] = float(value)
        return out

    # ---- parts and functions
    @property
    def parts(self) -> list[str]:
        return list(self.manifest.parts)

    def part(self, name: str) -> Part:
        if name not in NEEDS_OF_PART:      # e.g. "linear": a need, not a part that integrates
            raise MissingPart(f"part {name!r} is unknown: use one of {', '.join(NEEDS_OF_PART)}")
        if name not in self.manifest.parts:
            raise MissingPart(f"scene '{self.scene.name}' has no {name} model (model.needs = "
                              f"{self.scene.needs}): add \"{NEEDS_OF_PART.get(name, name)}\" to "
                              "model.needs in the scene")
        if name not in self._parts:
            self._parts[name] = Part(self, name)
        return self._parts[name]

    def has_function(self, name: str) -> bool:
        return name in self.manifest.functions

    def function(self, name: str) -> FunctionInfo:
        """The manifest's entry of a generated function (MissingPart if the model has none)."""
        info = self.manifest.functions.get(name)
        if info is None:
            raise MissingPart(f"scene '{self.scene.name}' has no generated function {name}")
        return info

    # ---- C backend
    @cached_property
    def library_path(self) -> Path:
        sources = [self.folder / "model.c"] + sorted(CSRC.glob("*.c"))
        return compile_shared(sources, include_dirs=(self.folder, CSRC))

    @cached_property
    def lib(self) -> ctypes.CDLL:
        """The compiled library (verified by cbuild before dlopen), its own table checked against
        the manifest before any function of it is called."""
        lib = self._dlopen()
        problem = disagreement(read_table(lib), self.manifest)
        if problem is not None:
            # the manifest was checked against model.c (sha256): the cached library, whose name is
            # the hash of this model.c, is another build's (copied or restored there, with its
            # stamp): deleting the model folder would not help; it is rebuilt, once
            print(f"levitron: the cached library {self.library_path} is not the one of "
                  f"{self.folder / 'model.c'} ({problem}): rebuilding it", file=sys.stderr)
            import _ctypes
            _ctypes.dlclose(lib._handle)
            discard(self.library_path)
            del self.library_path
            lib = self._dlopen()
            problem = disagreement(read_table(lib), self.manifest)
        if problem is not None:
            raise ArtefactError(f"{self.folder / 'manifest.json'} does not describe its model.c "
                                f"({problem}); {self.fix}")
        return lib

    def _dlopen(self) -> ctypes.CDLL:
        try:
            return ctypes.CDLL(str(self.library_path))
        except OSError as exc:
            raise ArtefactError(f"{self.library_path} cannot be loaded ({exc}); delete it and try "
                                "again") from None

    def symbol(self, name: str) -> str:
        """The C symbol of the generated function `name` (the manifest's symbol_prefix + name, which
        the library's own table confirms)."""
        return self.manifest.symbol_prefix + name

    def c_function(self, name: str):
        fn = self._cfuncs.get(name)
        if fn is None:
            self.function(name)
            fn = getattr(self.lib, self.symbol(name))
            fn.argtypes = [_DOUBLE_P, _DOUBLE_P, _DOUBLE_P]
            fn.restype = None
            self._cfuncs[name] = fn
        return fn

    def taylor_function(self, part: str):
        """`int <part>_taylor(in, p, order, out)` (manifest `taylor`), or None for a part without one."""
        info = self.manifest.taylor.get(part)
        if info is None:
            return None
        fn = self._cfuncs.get(info.function)
        if fn is None:
            fn = getattr(self.lib, self.symbol(info.function))
            fn.argtypes = [_DOUBLE_P, _DOUBLE_P, ctypes.c_int, _DOUBLE_P]
            fn.restype = ctypes.c_int
            self._cfuncs[info.function] = fn
        return fn

    def fast(self, name: str, p: np.ndarray | None = None) -> CFunction:
        """The generated C function `name` bound to parameters p (default the scene's) with
        preallocated buffers: for hot loops (root searches, Jacobian sweeps)."""
        info = self.function(name)
        p = self.p if p is None else np.asarray(p, dtype=float)
        if p.size != self.p.size:
            raise ValueError(f"{name}: expected {self.p.size} parameters, got {p.size}")
        return CFunction(self.c_function(name), info.n_in, info.n_out, p)

    # ---- CasADi backend
    def casadi(self, name: str):
        """The casadi.Function (in, p) -> out of `name`, its sizes checked against the manifest."""
        if name not in self._casadi:
            self._casadi[name] = self._load_casadi(self.function(name))
        return self._casadi[name]

    def _load_casadi(self, info: FunctionInfo):
        import casadi as ca
        path = self.folder / info.casadi
        try:
            fn = ca.Function.load(str(path))
        except RuntimeError as exc:
            why = (str(exc).strip().splitlines() or ["unreadable"])[-1]
            raise ArtefactError(f"{path} cannot be loaded by CasADi ({why}); {self.fix}") from None
        sizes = (fn.n_in(), fn.n_out()) == (2, 1) and (fn.nnz_in(0), fn.nnz_in(1), fn.nnz_out(0)) \
            == (info.n_in, self.p.size, info.n_out)
        if not sizes:
            raise ArtefactError(f"{path} does not take {info.n_in} inputs and {self.p.size} "
                                f"parameters to {info.n_out} outputs as manifest.json says; {self.fix}")
        return fn

    # ---- evaluation
    def call(self, name: str, x, p=None, backend: str = "c") -> np.ndarray:
        info = self.function(name)
        x = np.ascontiguousarray(x, dtype=float).reshape(-1)
        p = self.p if p is None else np.ascontiguousarray(p, dtype=float)
        if x.size != info.n_in or p.size != self.p.size:
            raise ValueError(f"{name}: expected {info.n_in} inputs and {self.p.size} parameters, "
                             f"got {x.size}, {p.size}")
        if backend == "c":
            return self._bound_function(name, p)(x)
        if backend == "casadi":
            return np.asarray(self.casadi(name)(x, p), dtype=float).reshape(-1)
        raise UserError(f"unknown backend {backend!r}: use 'c' or 'casadi'")

    def _bound_function(self, name: str, p: np.ndarray) -> CFunction:
        """fast(name, p), built once per function and thread and given p by a copy into its
        buffer: call's path (a launch's Legendre map makes eight calls, a run's summary more)."""
        cache = self._bound.__dict__
        f = cache.get(name)
        if f is None:
            f = cache[name] = self.fast(name, p)
        else:
            f.bind(p)
        return f

    def rows(self, name: str, X, p=None) -> np.ndarray:
        """The generated C function `name` at every row of X (rows, n_in) -> (rows, n_out), in one
        C call (runtime/csrc lev_rows): the invariants of a trajectory's samples, no Python loop."""
        info = self.function(name)
        X = np.ascontiguousarray(X, dtype=float).reshape(-1, info.n_in)
        p = self.p if p is None else np.ascontiguousarray(p, dtype=float)
        if p.size != self.p.size:
            raise ValueError(f"{name}: expected {self.p.size} parameters, got {p.size}")
        out = np.empty((X.shape[0], info.n_out))
        addr = self._rows_addr.get(name)
        if addr is None:
            addr = self._rows_addr[name] = ctypes.cast(self.c_function(name), ctypes.c_void_p).value
        self._lev_rows(addr, X.shape[0], info.n_in, info.n_out, X.ctypes.data, p.ctypes.data,
                       out.ctypes.data)
        return out

    @cached_property
    def _lev_rows(self):
        """runtime/csrc lev_rows(f, rows, n_in, n_out, X, p, out), plain int addresses."""
        return ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_long, ctypes.c_int, ctypes.c_int,
                                ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)(
            ctypes.cast(self.lib.lev_rows, ctypes.c_void_p).value)

    def onaxis(self, z, p=None, backend: str = "c") -> np.ndarray:
        """[Phi_0, ..., Phi_K](z) of the plate (thesis eq. 2.2.6 and eqs. 2.2.12-2.2.14)."""
        return self.call("onaxis", [float(z)], p, backend)

    def field(self, xyz, p=None, backend: str = "c") -> np.ndarray:
        """B(x, y, z) from the model's expansion (thesis eq. 2.2.7)."""
        return self.call("field", xyz, p, backend)


def load_model(scene: Scene) -> Model:
    """The loaded, verified model of a scene (derived first if needed); the scene's own overrides
    (the --set strings load_scene applied) and its file are the recipe that rebuilds it (Model.ref)."""
    found = locate(scene)
    return Model(scene, found.folder, found.manifest, found.fix)
