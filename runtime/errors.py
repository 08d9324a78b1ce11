"""Errors that the command line reports on one line (exit code 2)."""
from __future__ import annotations

__all__ = ["UserError"]


class UserError(Exception):
    """Bad input from the user: the message says what is wrong and how to fix it.

    Its text names the settings by the markers of runtime/words.py («t_end»), which each face
    words its own way (`words("cli")`: --t-end; `words("api")`: t_end), and writes its numbers
    with SI units as quantity markers (‹0.15|m›, words.py `si`), which `words(face, units)` shows
    in the scene's units. Where the error is about one setting it also carries it: `param` (its
    name, as the marker has it), `value` (what was given), `unit` (the value's SI unit, "" for
    none) and `hint` (how to fix it), for a program that wants to act on it rather than read it."""

    def __init__(self, message: str, *, param: str | None = None, value=None, unit: str = "",
                 hint: str | None = None):
        super().__init__(message)
        self.param, self.value, self.unit, self.hint = param, value, unit, hint

    def words(self, face: str, units=None) -> str:
        """The message as `face` ("cli", "api") says it, its quantities in `units` (a scene's
        runtime/ui/human.py Units; None: SI)."""
        from levitron.runtime.words import render
        return render(str(self), face, units)
