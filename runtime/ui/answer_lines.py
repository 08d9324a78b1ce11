"""An answer's plain-view lines for a face: the one wording of each answer (its `lines(units)`,
built from its JSON by a function beside the type), its quantities shown in the scene's display
units from their markers (runtime/ui/plain_text.py `shown`: cm, g; bare in a dimensionless scene)
and its settings' markers worded for the face ("api": the Python API's message, repr and notebook
table; None: kept, for a face that words the whole text itself: the command line and the report)."""
from __future__ import annotations

from levitron.runtime.ui.plain_text import shown
from levitron.runtime.words import render


def worded(lines, units, face: str | None = "api") -> list[str]:
    """The non-empty `lines`, their quantities in `units`, worded for `face` (None: settings kept)."""
    out = [shown(line, units) for line in lines if line]
    return out if face is None else [render(line, face, units) for line in out]


def as_written(r: dict, written, units) -> dict:
    """An answer's JSON `r` with each sentence key of `written` (its `said`: runtime/ui/plain_text.py)
    as written, with its quantities' markers, where the API's wording of it still stands."""
    if not written:
        return r
    from levitron.runtime.ui.plain_text import kept
    return {**r, **{k: kept(r.get(k), w, units) for k, w in written.items() if k in r}}


def keep_said(answer, **sentences) -> None:
    """In an answer's __post_init__: its sentences as written, once (a copy that the API's `speak`
    words keeps the first)."""
    if not answer.said:
        from levitron.runtime.ui.plain_text import said
        object.__setattr__(answer, "said", said(**{k: v for k, v in sentences.items() if v}))
