"""A run's samples as data: the table of a trajectory and its files (CSV, .npz).

Columns: t, the part's states (SI, manifest.json order), then the derived columns the summary
uses, each from a generated function over all samples (runtime/simulate/run.py): energy (H, thesis
2.3.9), L_z and L_n (derive/invariants.py) and tilt (the angle of the axis n = R_bs e_z to the
vertical, rad). `write` picks the format by the suffix; `read` gives the same table back.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui.validate import shown

SUFFIXES = (".csv", ".npz")
NAME_MAX = 255          # bytes of one file name (Linux, macOS)


def check_path(path, option: str = "--save") -> Path:
    """The --save path: a .csv or .npz file in an existing, writable folder, with a name the file
    system takes (one-line UserError otherwise, before the run: never a run lost at the end). `option`
    names the flag (the API passes its own words)."""
    if not isinstance(path, (str, os.PathLike)):
        raise UserError(f"{option} {path!r}: give a file name (text or a path) ending in .csv or .npz")
    p = Path(path)
    path = shown(path)
    if p.suffix.lower() not in SUFFIXES:
        raise UserError(f"{option} {path}: give a file ending in {' or '.join(SUFFIXES)} (CSV or numpy's .npz)")
    if len(os.fsencode(p.name)) > NAME_MAX:
        raise UserError(f"{option} {path}: the file name is {len(os.fsencode(p.name))} bytes long, "
                        f"more than the {NAME_MAX} a file system takes: give a shorter name")
    if p.is_dir():
        raise UserError(f"{option} {path} is a folder: give a file name ending in .csv or .npz")
    if not p.parent.exists():
        raise UserError(f"{option} {path}: the folder {shown(p.parent)} does not exist: create it first")
    if not p.parent.is_dir():
        raise UserError(f"{option} {path}: {shown(p.parent)} is a file, not a folder: save into a folder")
    if not os.access(p.parent, os.W_OK):
        raise UserError(f"{option} {path}: the folder {shown(p.parent)} is not writable: save elsewhere")
    return p


def write(path, names: list[str], table: np.ndarray, option: str = "--save") -> Path:
    """The table (rows: samples, columns: names) to path.csv (a header line, %.17g: every double
    round-trips) or path.npz (one array per column), through a temporary renamed into place
    (runtime/ui/atomic.py: never half a file, one whole file from concurrent writers)."""
    from levitron.runtime.ui.atomic import output
    p = check_path(path, option)
    with output(p, option) as tmp, open(tmp, "wb") as fh:
        if p.suffix.lower() == ".csv":
            np.savetxt(fh, table, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
        else:
            np.savez(fh, **{n: table[:, i] for i, n in enumerate(names)})
    return p


def read(path) -> tuple[list[str], np.ndarray]:
    """(names, table) of a file that `write` wrote."""
    p = Path(path)
    if p.suffix.lower() == ".csv":
        with open(p) as fh:
            names = fh.readline().strip().split(",")
        return names, np.atleast_2d(np.loadtxt(p, delimiter=",", skiprows=1))
    with np.load(p) as data:
        names = list(data.files)
        return names, np.column_stack([data[n] for n in names])
