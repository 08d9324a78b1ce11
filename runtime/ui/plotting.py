"""One place for matplotlib: figures made without pyplot, the house style, and saving a figure safely.

Nothing here touches matplotlib's global state (no backend switch, no rcParams written), so a plot
drawn from a notebook leaves the user's backend and style as they were. A plot function is

    @in_style                                          # the house style, for this drawing only
    def draw(data, path=None, ax=None):
        fig, axes = canvas(ax, figsize=(7, 3.6))        # the caller's Axes, or a new styled Figure
        axes.plot(...)
        if ax is None:
            fig.tight_layout()                          # never the caller's figure
        return finish(fig, path, ax=ax)                 # written when given a path; Figure or Axes

    check_plot_path(path)         # before the work: a bad output path is a one-line UserError
    styled()                      # the one look of every figure (fonts, grid, colours, size)
    figure(**kw)                  # a new Figure in that look, which keeps it when drawn anywhere
    save_figure(fig, path)        # the folder is made, the file appears whole or not at all
    band(ax, lo, hi, label)       # a shaded interval (the stable band) with its legend entry
"""
from __future__ import annotations

import functools
from pathlib import Path

from levitron.runtime.errors import UserError

PLOT_SUFFIXES = (".png", ".pdf", ".svg")


STYLE = {
    "figure.figsize": (7.5, 5.0),
    "figure.dpi": 110,
    "font.size": 10,
    "axes.titlesize": "medium",
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "legend.fontsize": "small",
    "legend.framealpha": 0.85,
    "lines.linewidth": 1.4,
}
BAND_COLOR = "#2ca02c"


def styled():
    """The one style of all figures (STYLE) as a context (matplotlib.rc_context): the figure is made,
    drawn and saved inside it, and the caller's rcParams are as they were after it."""
    import matplotlib
    return matplotlib.rc_context(STYLE)


def figure(**kw):
    """A new matplotlib Figure in the house style, made without pyplot (no backend, no figure
    manager: nothing to close); keyword arguments as matplotlib.figure.Figure's (figsize, ...).
    It draws in that style wherever it is drawn (a file, a notebook's cell)."""
    from levitron.runtime.ui.styled_figure import StyledFigure
    return StyledFigure(style=STYLE, **kw)


def canvas(ax=None, fig=None, *, figsize=None, nrows: int = 1, ncols: int = 1, **subplots):
    """(figure, axes) to draw into, matplotlib's `ax=` convention: the given `ax` (an Axes, or for a
    plot of nrows x ncols panels a list of that many) and its figure; else the panels made on the
    given `fig` (a Figure or SubFigure) or on a new figure(figsize=figsize). Call inside styled()."""
    if ax is not None and hasattr(ax, "figure"):
        return ax.figure, ax
    if ax is not None:
        import numpy as np
        panels = list(np.ravel(np.asarray(ax, dtype=object)))
        if len(panels) != nrows * ncols or not all(hasattr(a, "figure") for a in panels):
            raise UserError(f"ax: this plot draws {nrows * ncols} panels: give as many Axes (a list), or "
                            "fig= a Figure to draw them on, or neither for a figure of its own")
        return panels[0].figure, panels if len(panels) > 1 else panels[0]
    if fig is None:
        fig = figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, **subplots)


def finish(fig, path=None, option: str = "«plot»", ax=None):
    """A plot's answer: the figure written to `path` when one is given (save_figure), then the
    Figure, or the Axes the caller gave (`ax`)."""
    if path is not None:
        save_figure(fig, path, option)
    return fig if ax is None else ax


def in_style(draw):
    """Decorator: `draw` runs inside styled() (made and drawn in the house style)."""
    @functools.wraps(draw)
    def styled_draw(*args, **kwargs):
        with styled():
            return draw(*args, **kwargs)
    return styled_draw


def pyplot():
    """matplotlib.pyplot, imported on first use, for a script's own figures; the backend is left as
    matplotlib or the user chose it. The plots of the package use figure() and never pyplot."""
    import matplotlib.pyplot as plt
    return plt


def band(ax, lo: float, hi: float, label: str, axis: str = "x") -> None:
    """Shade [lo, hi] on `ax` (along x or y) as the stable band, with a legend entry."""
    shade = ax.axvspan if axis == "x" else ax.axhspan
    shade(lo, hi, color=BAND_COLOR, alpha=0.15, lw=0, label=label)


def check_plot_path(path, option: str = "«plot»") -> Path:
    """`path` as a plot file the command can write, checked before any work is done (nothing is
    created here): a suffix matplotlib writes (.png, .pdf, .svg), then every writer's check
    (runtime/ui/atomic.py check_target: not a folder, a name that fits, a writable folder or one
    that can be made). UserError, one line, otherwise."""
    from levitron.runtime.ui.atomic import check_target
    path = Path(path)
    suffixes = ", ".join(PLOT_SUFFIXES)
    if path.is_dir() or not path.name:
        check_target(path, option, "plot.png")
    if path.suffix.lower() not in PLOT_SUFFIXES:
        raise UserError(f"{option} {path}: the file name must end in one of {suffixes}, e.g. "
                        f"{option} {path.with_suffix('.png')}")
    return check_target(path, option, "plot.png")


def save_figure(fig, path, option: str = "«plot»") -> Path:
    """Write `fig` (a Figure, or a SubFigure: its whole figure) to `path` (checked by
    check_plot_path; its folder is made), in the house style. The figure is drawn into a temporary
    file beside the target and renamed into place (runtime/ui/atomic.py), so a failed write leaves
    nothing half-written. OSError becomes a one-line UserError. A figure made without pyplot
    (figure()) needs no closing; one that pyplot manages is left to its owner."""
    from levitron.runtime.ui.atomic import output
    path = check_plot_path(path, option)
    root = getattr(fig, "figure", None) or fig          # a SubFigure's whole figure
    with styled(), output(path, option, mkdir=True) as tmp:
        root.savefig(tmp, dpi=110, format=path.suffix[1:].lower())
    return path
