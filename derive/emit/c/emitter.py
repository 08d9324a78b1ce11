"""Emit model.c and model.h for a scene through the jinja2 templates beside this file.

Every generated C function is the symbol SYMBOL_PREFIX + its name (`lev_model_full_rhs`), so that no
model symbol can meet another library's. model.c also exports its own table, `lev_model_table()`: the
scene, the input hash, the symbol prefix, the parameter names in order, the state names of each part
and every function's name, n_in and n_out, as JSON
(split into short C string literals, joined by the reader). The runtime checks it against
manifest.json after loading the library and before any call (runtime/model/load.py).
"""
from __future__ import annotations

import json
from pathlib import Path

import jinja2

from ..lower import Lowered
from ..taylor import TAYLOR_MAX_ORDER, Tape, c_lines
from .printer import FMA_PRELUDE, LevitronCPrinter

TEMPLATES = Path(__file__).resolve().parent / "templates"
TABLE_FORMAT = 2          # 2: the table and the manifest carry symbol_prefix
SYMBOL_PREFIX = "lev_model_"   # the C symbol of every generated function: prefix + name (the table says it)
TABLE_CHUNK = 96          # characters of JSON per C string literal (C99 guarantees 4095)
LANES = 4                 # trajectories per call of a lane variant <name>_lanes (runtime/csrc)


def _env() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), keep_trailing_newline=True,
                              undefined=jinja2.StrictUndefined, autoescape=False)


def trig_lines(trig: list) -> list[str]:
    """sin and cos of one angle from one inline lev_sincos (runtime/csrc/lev_sincos.h); a lone one from libm."""
    by_angle: dict = {}
    for s, fn, a in trig:
        by_angle.setdefault(a, {})[fn] = s
    lines = []
    for a, fns in by_angle.items():
        if len(fns) == 2:
            lines.append(f"double {fns['sin']}, {fns['cos']};")
            lines.append(f"lev_sincos({a}, &{fns['sin']}, &{fns['cos']});")
        else:
            (fn, s), = fns.items()
            lines.append(f"const double {s} = {fn}({a});")
    return lines


def body_lines(f: Lowered, printer: LevitronCPrinter) -> list[str]:
    lines = trig_lines(f.trig)
    lines += [f"const double {s} = {printer.doprint(e)};" for s, e in f.body]
    lines += [f"out[{i}] = {printer.doprint(e)};" for i, e in enumerate(f.outputs)]
    return lines


def lane_lines(f: Lowered, printer: LevitronCPrinter) -> list[str]:
    """The body of the lane variant: the same statements, lane l of a structure of arrays
    (in[k LANES + l], out[k LANES + l]); sin and cos from lev_sincos_lanes (no branch, so the
    lanes loop vectorises), an angle beyond its range noted in `big` (the template then sends
    every lane through the scalar function, which falls back to libm)."""
    lines = []
    for line in body_lines(f, printer):
        if line.startswith("lev_sincos("):
            a = line[len("lev_sincos("):].split(",")[0]
            lines.append(f"big |= !(fabs({a}) < 1e5);")
            line = "lev_sincos_lanes(" + line[len("lev_sincos("):]
        elif line.startswith("out["):
            k, rest = line[len("out["):].split("]", 1)
            line = f"out[{k} * {LANES} + l]{rest}"
        lines.append(line)
    return lines


def taylor_entry(tape: Tape) -> dict:
    """What the manifest and the model's table say of a Taylor function (runtime/model/manifest.py)."""
    return {"function": tape.name, "n": tape.n, "max_order": TAYLOR_MAX_ORDER,
            "nodes": len(tape.nodes)}


def model_table(scene: str, input_hash: str, params: list[str], parts: dict,
                lowered: list[Lowered], tapes: dict[str, Tape]) -> dict:
    """What the compiled model says about itself (read by runtime/model/table.py)."""
    return {"format": TABLE_FORMAT, "scene": scene, "input_hash": input_hash,
            "symbol_prefix": SYMBOL_PREFIX, "parameters": list(params),
            "parts": {name: list(info["states"]) for name, info in parts.items()},
            "functions": {f.name: {"n_in": f.n_in, "n_out": f.n_out} for f in lowered},
            "taylor": {part: taylor_entry(t) for part, t in tapes.items()}}


def c_string_chunks(text: str, width: int = TABLE_CHUNK) -> list[str]:
    """`text` (ASCII) as C string literals of at most `width` characters of text each."""
    chunks = [text[i:i + width] for i in range(0, len(text), width)] or [""]
    return ['"' + c.replace("\\", "\\\\").replace('"', '\\"') + '"' for c in chunks]


def render(banner: str, guard: str, params: list[str], parts: dict, kmax: int,
           lowered: list[Lowered], table: dict, tapes: dict[str, Tape]) -> tuple[str, str]:
    """The text of model.h and model.c."""
    printer = LevitronCPrinter()
    funcs = []
    for f in lowered:
        funcs.append({"name": f.name, "symbol": SYMBOL_PREFIX + f.name, "doc": f.doc, "n_in": f.n_in,
                      "n_out": f.n_out, "ops": f.ops,
                      "inputs": f.inputs, "params": f.params, "lines": body_lines(f, printer),
                      "lane_lines": lane_lines(f, printer) if f.name.endswith("_rhs") else None})
    taylor = [{"name": t.name, "symbol": SYMBOL_PREFIX + t.name, "params": t.params,
               "lines": c_lines(t, printer),
               "nodes": len(t.nodes), "mults": t.mults_per_degree,
               "doc": f"{part} model: Taylor coefficients of the solution (derive/emit/taylor.py)"}
              for part, t in tapes.items()]
    env = _env()
    table_json = json.dumps(table, sort_keys=True, separators=(",", ":"), ensure_ascii=True)
    uses_sincos = any(line.startswith("lev_sincos(") for f in funcs for line in f["lines"])
    ctx = {"fma_prelude": FMA_PRELUDE, "uses_sincos": uses_sincos, "lanes": LANES, "banner": banner, "guard": guard,
           "params": params, "parts": parts, "kmax": kmax,
           "functions": funcs, "table_lines": c_string_chunks(table_json),
           "taylor": taylor, "taylor_max_order": TAYLOR_MAX_ORDER}
    return env.get_template("model.h.j2").render(**ctx), env.get_template("model.c.j2").render(**ctx)
