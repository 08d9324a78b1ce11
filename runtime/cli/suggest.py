""""did you mean ...?" for a misspelt flag or command name: the closest of what the parser knows
(difflib.get_close_matches), appended to argparse's own one-line message (runtime/cli/main.py Parser)."""
from __future__ import annotations

import argparse
import difflib
import re

CUTOFF = 0.6       # difflib's default: `--sucess-time` -> `--success-time`, `stabilty` -> `stability`


def closest(word: str, candidates) -> str | None:
    """The candidate closest to `word`, or None when none is close."""
    hits = difflib.get_close_matches(word, list(candidates), n=1, cutoff=CUTOFF)
    return hits[0] if hits else None


def subparser(parser: argparse.ArgumentParser, namespace) -> argparse.ArgumentParser | None:
    """The parser of the command `namespace` was parsed for (None: no subcommands, or none chosen)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices.get(getattr(namespace, action.dest or "", None))
    return None


def options_hint(parser: argparse.ArgumentParser, extras: list[str]) -> str:
    """"; did you mean --success-time?" for the unrecognised flags among `extras` that are close to
    one of the parser's option strings ("" where none is)."""
    known = [s for action in parser._actions for s in action.option_strings if s.startswith("--")]
    guesses = []
    for token in extras:
        if not token.startswith("-") or re.fullmatch(r"-[\d.]+(e[-+]?\d+)?", token):   # a value, a negative number
            continue
        flag = token.split("=", 1)[0]
        guess = closest(flag if flag.startswith("--") else "-" + flag, known)
        if guess and guess not in guesses:
            guesses.append(guess)
    return f"; did you mean {' or '.join(guesses)}?" if guesses else ""


def unrecognized(parser: argparse.ArgumentParser, namespace, extras: list[str]) -> str:
    """The one line of unrecognised arguments: the closest flags of the command, and its help."""
    sub = subparser(parser, namespace) or parser
    return (f"{parser.prog}: error: unrecognized arguments: {' '.join(extras)}{options_hint(sub, extras)} "
            f"(see `{sub.prog} --help`)\n")


def choice_hint(message: str) -> str:
    """argparse's "invalid choice: 'stabilty' (choose from 'derive', ...)" with "; did you mean
    stability?" after it, where one of the choices is close."""
    m = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)$", message)
    if not m:
        return message
    guess = closest(m.group(1), re.findall(r"'([^']*)'", m.group(2)) or m.group(2).split(", "))
    return f"{message}; did you mean {guess}?" if guess else message
