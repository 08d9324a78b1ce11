"""One place for matplotlib: the non-interactive backend, and saving a figure safely.

    check_plot_path(path)         # before the work: a bad output path is a one-line UserError
    style()                       # the one look of every figure (fonts, grid, colours, size)
    save_figure(fig, path)        # the folder is made, the file appears whole or not at all
    band(ax, lo, hi, label)       # a shaded interval (the stable band) with its legend entry
"""
from __future__ import annotations

from pathlib import Path

from levitron.runtime.errors import UserError

PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed), imported on first use."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


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


def style() -> None:
    """Apply the one style of all figures (matplotlib rcParams)."""
    pyplot().rcParams.update(STYLE)


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
    """Write `fig` to `path` (checked by check_plot_path; its folder is made) and close it. The
    figure is drawn into a temporary file beside the target and renamed into place
    (runtime/ui/atomic.py), so a failed write leaves nothing half-written. OSError becomes a
    one-line UserError."""
    from levitron.runtime.ui.atomic import output
    plt = pyplot()
    try:
        path = check_plot_path(path, option)
        with output(path, option, mkdir=True) as tmp:
            fig.savefig(tmp, dpi=110, format=path.suffix[1:].lower())
    finally:
        plt.close(fig)
    return path
