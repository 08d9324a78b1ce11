"""The set-up drawn to scale as an inline SVG: a vertical cut through the axis of the base, the top
at its hover height z_s (thesis 3.3.2-3.3.3), the stable band shaded and the critical height z_c
(thesis 3.3.3, where the band is widest), with dimensions in the scene's units
(runtime/ui/human.py Units; a dimensionless scene shows bare numbers).

    svg = drawing(setup, units, title)     # setup: runtime/simulate/setup_shape.py setup_of(..., bands=True)
"""
from __future__ import annotations

import html

from levitron.runtime.simulate.setup_shape import extent
from levitron.runtime.ui.human import Units

W, H = 640, 420          # the SVG's viewBox
MARGIN = 60


def _esc(s) -> str:
    return html.escape(str(s))


def drawing(setup: dict, u: Units, title: str = "") -> str:
    """The cut (module docstring) as one <svg> element, every length to one scale."""
    base, r, h = setup["base"], setup["top_radius"], max(setup["top_height"], 0.0)
    z_s, band, z_c = setup.get("z_s"), setup.get("band"), setup.get("z_c")
    half = max(extent(base), 2.5 * r, 0.3 * setup["scale"])
    thick = max([b.get("thickness", 0.0) for b in base], default=0.0)
    heights = [v for v in (z_s, z_c, *(band or ())) if v is not None] or [setup["scale"]]
    z_top = max(heights) + max(h, r) + 0.15 * half
    k = min((W - 2 * MARGIN) / (2 * half), (H - 2 * MARGIN) / (z_top + thick))
    x0, y0 = W / 2, H - MARGIN - thick * k            # the plate's top face, z = 0

    def X(x):
        return x0 + k * x

    def Y(z):
        return y0 - k * z

    out = [f'<svg viewBox="0 0 {W} {H}" width="{W}" style="max-width:100%;background:#fff;'
           'border:1px solid #ddd;font:12px sans-serif" role="img" aria-label="the set-up to scale">']
    if title:
        out.append(f'<text x="10" y="18" font-weight="bold">{_esc(title)}</text>')
    if band:
        out.append(f'<rect x="{MARGIN / 2}" y="{Y(band[1]):.1f}" width="{W - MARGIN}" '
                   f'height="{k * (band[1] - band[0]):.1f}" fill="#d7f0dc"/>')
        out.append(f'<text x="{W - MARGIN / 2 - 4}" y="{Y(band[0]) + 13:.1f}" text-anchor="end" '
                   f'fill="#287a3a">stable band {_esc(u.length_span(*band))}</text>')
    if z_c is not None:
        out.append(f'<line x1="{MARGIN / 2}" x2="{W - MARGIN / 2}" y1="{Y(z_c):.1f}" y2="{Y(z_c):.1f}" '
                   'stroke="#287a3a" stroke-dasharray="2 3"/>')
        out.append(f'<text x="{MARGIN / 2 + 2}" y="{Y(z_c) - 3:.1f}" fill="#287a3a">'
                   f'z_c = {_esc(u.length(z_c))}</text>')
    for b in base:
        t = b.get("thickness", 0.0)
        ht = max(k * t, 3.0)
        if b["kind"] == "rect":
            spans = ([(-b["half_x"], -b["r_in"]), (b["r_in"], b["half_x"])] if b.get("r_in", 0) > 0
                     else [(-b["half_x"], b["half_x"])])
        elif b["kind"] == "loop":
            for sx in (-1, 1):
                out.append(f'<circle cx="{X(sx * b["r_out"]):.1f}" cy="{y0:.1f}" r="4" fill="#c77d1a"/>')
            out.append(f'<text x="{x0}" y="{y0 + 18:.1f}" text-anchor="middle">loop of radius '
                       f'{_esc(u.length(b["r_out"]))}</text>')
            continue
        else:
            spans = ([(-b["r_out"], -b["r_in"]), (b["r_in"], b["r_out"])] if b["r_in"] > 0
                     else [(-b["r_out"], b["r_out"])])
        for a, c in spans:
            out.append(f'<rect x="{X(a):.1f}" y="{y0:.1f}" width="{k * (c - a):.1f}" height="{ht:.1f}" '
                       'fill="#8a8f99" stroke="#555"/>')
        outer = b.get("r_out", b.get("half_x", 0.0))
        dims = [f"{'width' if b['kind'] == 'rect' else 'diameter'} {u.length(2 * outer)}"]
        if b.get("r_in", 0) > 0:
            dims.append(f"hole {u.length(2 * b['r_in'])}")
        if t > 0:
            dims.append(f"thickness {u.length(t)}")
        yd = y0 + ht + 16
        out.append(f'<line x1="{X(-outer):.1f}" x2="{X(outer):.1f}" y1="{yd - 4:.1f}" y2="{yd - 4:.1f}" '
                   'stroke="#333" marker-start="url(#lv-a)" marker-end="url(#lv-a)"/>')
        out.append(f'<text x="{x0}" y="{yd + 10:.1f}" text-anchor="middle">base: {_esc(", ".join(dims))}</text>')
    if not base:
        out.append(f'<text x="{x0}" y="{y0 + 16:.1f}" text-anchor="middle">the field is given by a formula: '
                   'no base to draw</text>')
    out.append(f'<line x1="{MARGIN / 2}" x2="{W - MARGIN / 2}" y1="{y0}" y2="{y0}" stroke="#999" '
               'stroke-width="0.5"/>')
    if z_s is not None:
        hh = max(k * h, 2.0)
        out.append(f'<rect x="{X(-r):.1f}" y="{Y(z_s) - hh / 2:.1f}" width="{2 * k * r:.1f}" height="{hh:.1f}" '
                   'fill="#c0392b" stroke="#7b241c"/>')
        out.append(f'<line x1="{x0}" x2="{x0}" y1="{Y(z_s) - hh / 2 - k * r:.1f}" y2="{Y(z_s) + hh / 2 + 4:.1f}" '
                   'stroke="#111"/>')
        xa = X(-half * 0.75)
        out.append(f'<line x1="{xa:.1f}" x2="{xa:.1f}" y1="{y0:.1f}" y2="{Y(z_s):.1f}" stroke="#333" '
                   'marker-start="url(#lv-a)" marker-end="url(#lv-a)"/>')
        out.append(f'<text x="{xa + 4:.1f}" y="{(y0 + Y(z_s)) / 2:.1f}">hover height z_s = '
                   f'{_esc(u.length(z_s))}</text>')
        out.append(f'<text x="{X(r) + 8:.1f}" y="{Y(z_s) + 4:.1f}">top: disc {_esc(u.length(2 * r))} across'
                   + (f', {_esc(u.length(h))} high' if h > 0 else "") + '</text>')
    else:
        out.append(f'<text x="{x0}" y="{MARGIN:.1f}" text-anchor="middle">the top has no stable hover height</text>')
    out.append('<defs><marker id="lv-a" viewBox="0 0 10 10" refX="5" refY="5" markerWidth="6" markerHeight="6" '
               'orient="auto-start-reverse"><path d="M 0 0 L 10 5 L 0 10 z"/></marker></defs></svg>')
    return "".join(out)


def page(svg: str, title: str, note: str) -> str:
    """The drawing as a page of its own (`figures --setup`)."""
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{_esc(title)}</title></head><body style=\"font-family:sans-serif\">{svg}"
            f"<p>{_esc(note)}</p></body></html>\n")


NOTE = ("Drawn to scale: a vertical cut through the axis of the base. The top is the uniform disc of "
        "its mass and axial moment C (radius sqrt(2 C / m)); the scene gives no other size of it.")
