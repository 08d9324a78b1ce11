"""Emit model.c and model.h for a scene through the jinja2 templates beside this file."""
from __future__ import annotations

from pathlib import Path

import jinja2

from ..lower import Lowered
from .printer import LevitronCPrinter

TEMPLATES = Path(__file__).resolve().parent / "templates"


def _env() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), keep_trailing_newline=True,
                              undefined=jinja2.StrictUndefined, autoescape=False)


def body_lines(f: Lowered, printer: LevitronCPrinter) -> list[str]:
    lines = [f"const double {s} = {fn}({a});" for s, fn, a in f.trig]
    lines += [f"const double {s} = {printer.doprint(e)};"
              for s, e in f.phi]
    lines += [f"const double {s} = {printer.doprint(e)};" for s, e in f.main]
    lines += [f"out[{i}] = {printer.doprint(e)};" for i, e in enumerate(f.outputs)]
    return lines


def render(banner: str, guard: str, params: list[str], parts: dict, kmax: int,
           lowered: list[Lowered]) -> tuple[str, str]:
    """The text of model.h and model.c."""
    printer = LevitronCPrinter()
    funcs = []
    for f in lowered:
        funcs.append({"name": f.name, "doc": f.doc, "n_in": f.n_in, "n_out": f.n_out, "ops": f.ops,
                      "inputs": f.inputs, "params": f.params, "lines": body_lines(f, printer)})
    env = _env()
    ctx = {"banner": banner, "guard": guard, "params": params, "parts": parts, "kmax": kmax,
           "functions": funcs}
    return env.get_template("model.h.j2").render(**ctx), env.get_template("model.c.j2").render(**ctx)
