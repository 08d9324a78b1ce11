"""An answer's plain view in a notebook and a repr: the lines its `lines(units)` writes, one place.

    html_table("Stability", answer.lines(units), figure=answer.plot())   -> "<table>...</table>"
    text_repr("Stability", [*answer.lines(units)[:2], "success=True"])  -> "Stability(line; line; success=True)"

The lines are the plain view the command line prints (already worded, in the scene's display
units); these helpers only lay them out. A line "key: value" becomes a row of two cells, any other
line a row of one. The figure (a matplotlib Figure, optional) is drawn below the table as an inline
SVG and closed, so a notebook that shows many answers does not keep their figures open.
"""
from __future__ import annotations

import base64
import html
import io

__all__ = ["html_table", "text_repr"]


def _row(line: str) -> str:
    key, sep, value = line.partition(": ")
    if sep and key and len(key) <= 40 and "  " not in key:
        return f"<tr><th style='text-align:left'>{html.escape(key.strip())}</th><td>{html.escape(value)}</td></tr>"
    return f"<tr><td colspan='2'>{html.escape(line.strip())}</td></tr>"


def _figure_html(figure) -> str:
    """The matplotlib `figure` as an inline SVG (a PNG in base64 where SVG fails); closed after."""
    if figure is None:
        return ""
    try:
        buf = io.StringIO()
        try:
            figure.savefig(buf, format="svg", bbox_inches="tight")
            svg = buf.getvalue()
            start = svg.find("<svg")
            return f"<div>{svg[start:] if start >= 0 else svg}</div>"
        except (ValueError, TypeError, RuntimeError):
            raw = io.BytesIO()
            figure.savefig(raw, format="png", bbox_inches="tight")
            data = base64.b64encode(raw.getvalue()).decode("ascii")
            return f"<div><img src='data:image/png;base64,{data}'/></div>"
    finally:
        import matplotlib.pyplot as plt
        plt.close(figure)


def html_table(title: str, lines: list[str], figure=None) -> str:
    """`lines` (the plain view) as a small HTML table headed by `title`, the text escaped, with
    `figure` (a matplotlib Figure or None) drawn below it and closed."""
    rows = "".join(_row(line) for line in lines if line and line.strip())
    head = f"<caption style='text-align:left'><b>{html.escape(title)}</b></caption>"
    return f"<div><table>{head}{rows}</table>{_figure_html(figure)}</div>"


def text_repr(name: str, lines: list[str]) -> str:
    """`name(line; line; ...)`: the repr of an answer, one line, from the lines the caller picks
    of its plain view (a short repr: the answer's first lines and "success=..."), blank ones left out."""
    body = [" ".join(line.split()) for line in lines if line and line.strip()]
    return f"{name}({'; '.join(body)})"
