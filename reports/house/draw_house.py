"""Draws runtime/physics/ as its folders (boxes, one column each) holding their modules, and the imports
between the modules as arrows (function-level imports counted, as tests/house/test_layers.py counts them).
Columns run left to right in ORDER where a folder is named there, then alphabetically; an arrow that runs
to a column on its right (an import up the order) is drawn red.

    python reports/house/draw_house.py OUT.png [PHYSICS_DIR]     (PHYSICS_DIR: runtime/physics if left out)
"""
from __future__ import annotations

import ast
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Rectangle  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
PHYSICS = Path(sys.argv[2]).resolve() if len(sys.argv) > 2 else ROOT / "runtime" / "physics"
ORDER = ("(top)", "field", "plates", "routes", "equilibrium", "apparatus", "stability")


def modules():
    files = sorted(p for p in PHYSICS.rglob("*.py") if "__pycache__" not in p.parts)
    out = {}
    for p in files:
        rel = p.relative_to(PHYSICS)
        parts = [*rel.parts[:-1]] + ([] if p.name == "__init__.py" else [p.stem])
        out[".".join(["levitron.runtime.physics", *parts])] = p
    return out


def edges(mods):
    found = set()
    for name, path in mods.items():
        for node in ast.walk(ast.parse(path.read_text())):
            targets = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                subs = [f"{node.module}.{a.name}" for a in node.names if f"{node.module}.{a.name}" in mods]
                targets = subs or [node.module]      # `from package import module`: the module
            for t in targets:
                if t in mods and t != name:
                    found.add((name, t))
    return found


def folder(name):
    parent = MODS[name].parent.relative_to(PHYSICS).as_posix()
    return "(top)" if parent == "." else parent


MODS = modules()


def main(out):
    mods = MODS
    arrows = edges(mods)
    folders = sorted({folder(m) for m in mods}, key=lambda f: (ORDER.index(f) if f in ORDER else len(ORDER), f))
    rank = {f: i for i, f in enumerate(folders)}
    members = {f: sorted(m for m in mods if folder(m) == f) for f in folders}
    tall = max(len(v) for v in members.values())
    fig, ax = plt.subplots(figsize=(3.2 * len(folders) + 2, 0.42 * tall + 2.5))
    pos = {}
    for f in folders:
        x = rank[f] * 3.2
        ax.add_patch(Rectangle((x - 1.35, -len(members[f]) - 0.3), 2.7, len(members[f]) + 0.9,
                               fill=False, lw=1.2, ec="0.3"))
        ax.text(x, 0.25, f"physics/{f}" if f != "(top)" else "physics/", ha="center", weight="bold", fontsize=9)
        for i, m in enumerate(members[f]):
            pos[m] = (x, -i - 0.5)
            short = mods[m].relative_to(PHYSICS).as_posix()
            ax.text(x, -i - 0.5, short.split("/")[-1], ha="center", va="center", fontsize=7,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="0.75", lw=0.5))
    up = 0
    for a, b in sorted(arrows):
        fa, fb = folder(a), folder(b)
        back = rank[fb] > rank[fa]
        up += back
        rad = 0.5 if fa == fb else 0.05
        ax.add_patch(FancyArrowPatch(pos[a], pos[b], connectionstyle=f"arc3,rad={rad}", arrowstyle="-|>",
                                     mutation_scale=6, lw=0.5, color="tab:red" if back else "0.45", alpha=0.6,
                                     shrinkA=6, shrinkB=6))
    between = sum(folder(a) != folder(b) for a, b in arrows)
    ax.set_title(f"runtime/physics: {len(mods)} modules in {len(folders)} folders, {len(arrows)} imports "
                 f"({between} between folders, {up} up the order, red)", fontsize=10)
    ax.set_xlim(-2.4, 3.2 * (len(folders) - 1) + 2.4)
    ax.set_ylim(-tall - 0.8, 0.9)
    ax.axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])
