"""No sentence below cli/ spells a command-line flag; every marker names a real option (issue 29).

runtime/words.py: the runtime names a setting by a marker («t_end») and each face words it; these
tests hold that the markers are the only way (a flag written out in a runtime sentence would reach
the API as a flag again) and that every marker means an option the command line has."""
from __future__ import annotations

import argparse
import ast
import re
from pathlib import Path

import pytest

from levitron.runtime.cli.main import build_parser
from levitron.runtime.words import _API_METHOD, MARKER, render, speak

ROOT = Path(__file__).resolve().parents[2]
RUNTIME = ROOT / "runtime"
FLAG = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]+")
# report/rebuild.py writes the shell command that rebuilds a page: a command line, not a sentence
COMMAND_LINES = {"runtime/report/rebuild.py": "the shell command that rebuilds the report page"}


def _strings(tree: ast.AST):
    """(string constant, its parent) of every string that is not a docstring."""
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
            and n.body and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    for parent in ast.walk(tree):
        for child in ast.iter_child_nodes(parent):
            if isinstance(child, ast.Constant) and isinstance(child.value, str) and id(child) not in docs:
                yield child, parent


def _argv(node: ast.Constant, parent: ast.AST) -> bool:
    """An argument vector's word: the whole string is one flag, in a list or tuple (a command the
    runtime runs: the bench timing the CLI, the derivation, `cc --version`) or given to
    add_argument (a bench script's own options)."""
    if not FLAG.fullmatch(node.value):
        return False
    if isinstance(parent, (ast.List, ast.Tuple)):
        return True
    return isinstance(parent, ast.Call) and getattr(parent.func, "attr", None) == "add_argument"


def _modules():
    for path in sorted(RUNTIME.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if not rel.startswith("runtime/cli/"):
            yield rel, ast.parse(path.read_text())


def test_no_runtime_sentence_below_cli_spells_a_flag():
    bad = [f"{rel}:{node.lineno}: {FLAG.search(node.value).group()}"
           for rel, tree in _modules() if rel not in COMMAND_LINES
           for node, parent in _strings(tree) if FLAG.search(node.value) and not _argv(node, parent)]
    assert bad == [], "write the setting as a marker («t_end», runtime/words.py):\n" + "\n".join(bad)


def test_the_check_finds_a_flag_in_a_sentence_and_spares_an_argv():
    """The rule above can fail: a planted sentence is found, an argv word is not."""
    tree = ast.parse('raise UserError(f"pass e.g. --t-end 1, not {x}")\ncmd = [exe, "--json"]\n'
                     'write_text(p, option="--out")\n')
    found = [node.value for node, parent in _strings(tree) if FLAG.search(node.value) and not _argv(node, parent)]
    assert found == ["pass e.g. --t-end 1, not ", "--out"]


def _options() -> set[str]:
    """Every option of every command, as a marker names it ("t_end" for --t-end)."""
    out = set()
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            for parser in action.choices.values():
                out |= {s[2:].replace("-", "_") for a in parser._actions for s in a.option_strings
                        if s.startswith("--")}
    return out


def test_every_marker_names_an_option_of_the_command_line():
    options, commands = _options(), set(build_parser()._subparsers._group_actions[0].choices)
    bad = []
    for rel, tree in _modules():
        for node, _ in _strings(tree):
            for m in MARKER.finditer(node.value):
                name, value = m.groups()
                if "{" in name:
                    continue
                ok = (value in commands and value in _API_METHOD) if name == "levitron" else name in options
                if not ok:
                    bad.append(f"{rel}:{node.lineno}: {m.group()}")
    assert bad == []


@pytest.mark.parametrize("face", ["cli", "api"])
def test_speak_words_every_sentence_of_an_answer(face):
    """An answer's sentences, nested in dicts, lists and dataclasses, are worded; numbers and
    numeric arrays pass as they are (the same object)."""
    import dataclasses

    import numpy as np

    @dataclasses.dataclass(frozen=True)
    class Answer:
        reason: str
        warnings: list
        details: dict
        numbers: np.ndarray
        reasons: np.ndarray

    xs = np.arange(3.0)
    a = Answer("raise «t_end»", ["widen «vary»"], {"note": "«set=top.mass=0.05»", "k": 1.5}, xs,
               np.array([None, "«tol=1e-9»"], dtype=object))
    b = speak(a, face)
    flag = face == "cli"
    assert b.reason == ("raise --t-end" if flag else "raise t_end")
    assert b.warnings == [render("widen «vary»", face)] and b.details["k"] == 1.5
    assert b.details["note"] == ("--set top.mass=0.05" if flag else "overrides={'top.mass': 0.05}")
    assert b.numbers is xs and list(b.reasons) == [None, "--tol 1e-9" if flag else "tol=1e-9"]
    assert a.reason == "raise «t_end»"          # the answer itself is not changed


# ---------------------------------------------------------------- quantities in the scene's units

SI_UNIT = r"A m\^2|kg m\^2|m/s\^2|m/s|A/m|T m|J m|N/m|rad/s|mT|Hz|rpm|kg|N|T|A|m|s"
AFTER_A_NUMBER = re.compile(rf"^ ({SI_UNIT})(?![\w^/])|\d ({SI_UNIT})(?![\w^/])")
AS_A_WORD = re.compile(rf"\b(in|number) ({SI_UNIT})(?![\w^/])|\(({SI_UNIT})\)|\b(metres?|meters?|kilograms?)\b")
# magpylib speaks SI whatever the scene: its collection's positions are in m, its magnetisation in A/m
SI_ALWAYS = {"levitron/from_magpylib.py": "magpylib's own SI inputs, before any scene"}


def _unit_spelt(message: ast.AST) -> str | None:
    """The SI unit an error message's literal text spells after a number or a value (an f-string's
    field) or names as a word, outside a quantity marker; None if it spells none."""
    for node in ast.walk(message):
        if not isinstance(node, ast.JoinedStr | ast.Constant):
            continue
        parts = node.values if isinstance(node, ast.JoinedStr) else [node]
        for before, part in zip([None, *parts], parts):
            if not (isinstance(part, ast.Constant) and isinstance(part.value, str)):
                continue
            text = part.value
            hit = AS_A_WORD.search(text) or re.search(rf"\d ({SI_UNIT})(?![\w^/])", text)
            if isinstance(before, ast.FormattedValue):
                hit = hit or AFTER_A_NUMBER.match(text)
            if hit:
                return hit.group()
    return None


def _errors(roots):
    """(module, call) of every UserError the source makes, its subclasses' (NoEquilibrium, ...) too."""
    trees = {path.relative_to(ROOT).as_posix(): ast.parse(path.read_text())
             for root in roots for path in sorted(root.rglob("*.py"))}
    kinds = {"UserError"} | {n.name for tree in trees.values() for n in ast.walk(tree)
                             if isinstance(n, ast.ClassDef)
                             and any(getattr(b, "id", None) == "UserError" for b in n.bases)}
    for rel, tree in trees.items():
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and node.args
                    and getattr(node.func, "id", getattr(node.func, "attr", None)) in kinds):
                yield rel, node


def test_no_error_spells_an_si_unit_outside_a_quantity():
    """A UserError's number with an SI unit is a quantity marker (runtime/words.py `si`), which
    each face shows in the scene's units: a dimensionless scene's error has no m, kg or s (before,
    a regex, ui/human.py restate, dropped them from the finished text, and with them the seconds
    of a wall time, which are the computer's in every scene)."""
    bad = [f"{rel}:{node.lineno}: {unit!r}" for rel, node in _errors((RUNTIME, ROOT / "levitron"))
           if rel not in SI_ALWAYS and (unit := _unit_spelt(node.args[0])) is not None]
    assert bad == [], "write the number as si(value, unit) (runtime/words.py):\n" + "\n".join(bad)


def test_the_unit_check_finds_a_unit_and_spares_a_quantity():
    def spelt(src: str):
        return _unit_spelt(ast.parse(src, mode="eval").body.args[0])
    assert spelt('UserError(f"z = {z:.6g} m is too low")') == " m"
    assert spelt('UserError(f"step h={h} s; pass a number in s")') == "in s"
    assert spelt('UserError("give a height (m) above the plate")') == "(m)"
    assert spelt('UserError("give three numbers X,Y,Z in metres")') == "metres"
    assert spelt('UserError(f"z = {si(z, \'m\')} is too low, {n} steps, {mass} kg")') == " kg"
    assert spelt('UserError(f"z = {si(z, \'m\')} is too low after {n} steps")') is None


@pytest.mark.parametrize("si_scene,shown", [
    (True, "z = 0.1574 m, spin 3 rad/s over 5 s, a height in m, [0.1, 0.2] kg"),
    (False, "z = 0.1574, spin 3 rad/time over 5 time units, a height in scene units, [0.1, 0.2]"),
])
def test_a_quantity_is_shown_in_the_scenes_units(si_scene, shown):
    from levitron.runtime.errors import UserError
    from levitron.runtime.ui.human import Units
    from levitron.runtime.words import si, si_unit
    text = (f"z = {si(0.1574, 'm')}, spin {si(3, 'rad/s')} over {si(5.0, 's', 'g')}, a height in "
            f"{si_unit('m')}, {si('[0.1, 0.2]', 'kg')}")
    for face in ("cli", "api"):
        assert render(text, face, Units(si=si_scene)) == shown
        assert UserError(text).words(face, Units(si=si_scene)) == shown
    assert render(text, "cli") == render(text, "cli", Units(si=True))      # no scene: SI, the JSON's
