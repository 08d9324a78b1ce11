"""The table a compiled model exports about itself, and its check against the manifest.

model.c defines `const char *const *lev_model_table(void)`: NULL-terminated pieces of one JSON
object (derive/emit/c/emitter.py): scene, input hash, the prefix of every function's C symbol,
parameter names in order, the states of each
part, each function's n_in and n_out, and each Taylor function's sizes. Nothing is called in a
model until its table agrees with the manifest, so no buffer size is taken on trust.
"""
from __future__ import annotations

import ctypes
import json

from levitron.runtime.model.manifest import Manifest

TABLE_SYMBOL = "lev_model_table"
MAX_PIECES = 100_000


def read_table(lib: ctypes.CDLL) -> dict | None:
    """The library's table as a dict; None when it exports none or it is not a JSON object."""
    try:
        fn = getattr(lib, TABLE_SYMBOL)
    except AttributeError:
        return None
    fn.argtypes = []
    fn.restype = ctypes.POINTER(ctypes.c_char_p)
    pieces = fn()
    parts = []
    for i in range(MAX_PIECES):
        if pieces[i] is None:
            break
        parts.append(pieces[i])
    try:
        table = json.loads(b"".join(parts).decode("ascii"))
    except (UnicodeDecodeError, json.JSONDecodeError):
        return None
    return table if isinstance(table, dict) else None


def table_of(manifest: Manifest) -> dict:
    """What the table of the model described by `manifest` must say."""
    return {"scene": manifest.scene, "input_hash": manifest.input_hash,
            "symbol_prefix": manifest.symbol_prefix, "parameters": list(manifest.parameters),
            "parts": {name: list(p.states) for name, p in manifest.parts.items()},
            "functions": {name: {"n_in": f.n_in, "n_out": f.n_out}
                          for name, f in manifest.functions.items()},
            "taylor": {part: {"function": t.function, "n": t.n, "max_order": t.max_order,
                              "nodes": t.nodes} for part, t in manifest.taylor.items()}}


def disagreement(table: dict | None, manifest: Manifest) -> str | None:
    """Where the compiled model's table and the manifest differ (one phrase), or None."""
    if table is None:
        return f"the compiled model exports no readable {TABLE_SYMBOL}() (derived by an older levitron?)"
    want = table_of(manifest)
    for key in ("scene", "input_hash", "symbol_prefix", "parameters", "parts", "taylor"):
        if table.get(key) != want[key]:
            return f"{key}: the compiled model.c has {table.get(key)}, manifest.json {want[key]}"
    have = table.get("functions")
    if not isinstance(have, dict) or set(have) != set(want["functions"]):
        got = sorted(have) if isinstance(have, dict) else have
        return f"functions: the compiled model.c has {got}, manifest.json {sorted(want['functions'])}"
    for name, sizes in want["functions"].items():
        got = have[name]
        if got != sizes:
            got = (f"n_in = {got.get('n_in')}, n_out = {got.get('n_out')}" if isinstance(got, dict)
                   else repr(got))
            return (f"functions.{name}: the compiled model.c has {got}, manifest.json "
                    f"n_in = {sizes['n_in']}, n_out = {sizes['n_out']}")
    return None
