"""A matplotlib Figure that draws in a style of its own (runtime/ui/plotting.py STYLE, given when it
is made) wherever it is drawn: saved to a file, or shown by a notebook after the plot returned it.
The style holds for the drawing only (matplotlib.rc_context), so the caller's rcParams stay as they
were. Imported on first use (plotting.figure), so importing plotting costs no matplotlib."""
from __future__ import annotations

import matplotlib
from matplotlib.figure import Figure


class StyledFigure(Figure):
    """matplotlib.figure.Figure drawn inside matplotlib.rc_context(style): ticks and labels made
    while drawing (a notebook's redraw at another size) get the same look as the saved file's."""

    def __init__(self, *args, style: dict, **kwargs):
        with matplotlib.rc_context(style):
            super().__init__(*args, **kwargs)
        self.style = dict(style)

    def draw(self, renderer):
        with matplotlib.rc_context(self.style):
            return super().draw(renderer)
