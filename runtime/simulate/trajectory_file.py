"""A run's samples as data: the table of a trajectory and its files (CSV, .npz, Parquet).

Columns: t, the part's states (SI, manifest.json order), then the derived columns the summary
uses, each from a generated function over all samples (runtime/simulate/run.py): energy (H, thesis
2.3.9), L_z and L_n (derive/invariants.py) and tilt (the angle of the axis n = R_bs e_z to the
vertical, rad). `write` picks the format by the suffix; `read` gives the same table back.
`write_columns` / `read_columns` do the same for named columns that may hold text (the launches
of `levitron launch --save`, runtime/scan/launch_odds.py, with their verdicts). Every file is
written to a temporary file in the same folder and renamed (runtime/ui/atomic.py): nothing
half-written is left behind.
Every file the answers write names its columns' units (`units`: {column: unit}; `read_units` reads
them back): a CSV's first line is the comment `# units: t=s, x=m, ...` (column=unit, ", " between;
pandas: `read_csv(path, comment="#")`; numpy: `loadtxt(path, delimiter=",", skiprows=2)`), then
the header of names; a .npz holds the entry "units", the JSON text of the map (a 0-d string array,
not a column; left out where a column is named "units"); a Parquet file's schema metadata holds
the key "units", the same JSON. The units are SI ("1": a pure number, "text": a word) in an SI
scene, the scene's in a dimensionless one (runtime/ui/frames.py shown).
Parquet needs pyarrow (an optional package: `pip install pyarrow`); without it a .parquet path is
refused before the run.
"""
from __future__ import annotations

import csv
import json
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui.validate import shown

SUFFIXES = (".csv", ".npz", ".parquet")
FORMATS = ".csv, .npz or .parquet"
UNITS_LINE = "# units: "      # a CSV's first line: the columns' units (module docstring)
UNITS_KEY = "units"           # the .npz entry and the Parquet schema metadata key of the same


def _pyarrow():
    """pyarrow's parquet module, or None where pyarrow is not installed."""
    try:
        import pyarrow
        import pyarrow.parquet as pq
    except ImportError:
        return None
    return pyarrow, pq


def check_path(path, flag: str = "«save»") -> Path:
    """The --save path: a .csv, .npz or .parquet file, then every writer's check (runtime/ui/atomic.py
    check_target: not a folder, a name the file system takes, a writable folder or one that can be
    made; one-line UserError otherwise, before the run: never a run lost at the end).
    `flag` names the option (the API passes its own words)."""
    if not isinstance(path, (str, os.PathLike)):
        raise UserError(f"{flag} {path!r}: give a file name (text or a path) ending in {FORMATS}")
    p = Path(path)
    path = shown(path)
    if p.suffix.lower() not in SUFFIXES:
        raise UserError(f"{flag} {path}: give a file ending in {FORMATS} (CSV, numpy's .npz or Parquet)")
    if p.suffix.lower() == ".parquet" and _pyarrow() is None:
        raise UserError(f"{flag} {path}: Parquet needs pyarrow, which is not installed: pip install "
                        "pyarrow, or save to .csv or .npz")
    from levitron.runtime.ui.atomic import check_target
    check_target(p, flag, "run.csv")
    return p


def _csv(tmp: Path, columns: Mapping[str, np.ndarray], units: Mapping[str, str] | None = None) -> None:
    """The units' comment line (where given), a header line, then one row per sample: numbers as
    %.17g (every double round-trips), text as is."""
    cols = [(np.asarray(v).dtype.kind in "fiub", np.asarray(v)) for v in columns.values()]
    with open(tmp, "w", newline="") as fh:
        if units:
            fh.write(UNITS_LINE + ", ".join(f"{n}={units.get(n, '')}" for n in columns) + "\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(list(columns))
        for i in range(len(cols[0][1]) if cols else 0):
            w.writerow([format(float(a[i]), ".17g") if num else str(a[i]) for num, a in cols])


def _units_json(columns: Mapping[str, np.ndarray], units: Mapping[str, str]) -> str:
    return json.dumps({n: units.get(n, "") for n in columns})


def _npz(tmp: Path, columns: Mapping[str, np.ndarray], units: Mapping[str, str] | None = None) -> None:
    extra = {UNITS_KEY: np.array(_units_json(columns, units))} if units and UNITS_KEY not in columns else {}
    with open(tmp, "wb") as fh:        # a handle: np.savez adds ".npz" to a name not ending in it
        np.savez(fh, **{n: np.asarray(v) for n, v in columns.items()}, **extra)


def _parquet(tmp: Path, columns: Mapping[str, np.ndarray], units: Mapping[str, str] | None = None) -> None:
    pa, pq = _pyarrow()
    table = pa.table({n: np.asarray(v) for n, v in columns.items()})
    if units:
        table = table.replace_schema_metadata({**(table.schema.metadata or {}),
                                               UNITS_KEY.encode(): _units_json(columns, units).encode()})
    pq.write_table(table, str(tmp))


WRITERS = {".csv": _csv, ".npz": _npz, ".parquet": _parquet}


def write_columns(path, columns: Mapping[str, np.ndarray], flag: str = "«save»",
                  units: Mapping[str, str] | None = None) -> Path:
    """Named 1-D columns of one length (numbers or text) to path, the format by its suffix, through
    a temporary beside it renamed onto path (runtime/ui/atomic.py: never half a file, one whole
    file from concurrent writers, mode 0666 less the umask, a killed writer's temporary swept);
    units {column: unit}, where given, written with them (module docstring)."""
    from levitron.runtime.ui.atomic import output
    p = check_path(path, flag)
    with output(p, flag) as tmp:
        WRITERS[p.suffix.lower()](tmp, columns, units)
    return p


def _typed(values: list[str]) -> np.ndarray:
    """A CSV column as floats where every entry is a number, else as text."""
    try:
        return np.array([float(v) for v in values])
    except ValueError:
        return np.array(values)


def read_columns(path) -> dict[str, np.ndarray]:
    """{name: column} of a file that `write_columns` (or `write`) wrote."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".csv":
        with open(p, newline="") as fh:
            rows = list(csv.reader(line for line in fh if not line.startswith("#")))
        names, body = rows[0], rows[1:]
        return {n: _typed([r[j] for r in body]) for j, n in enumerate(names)}
    if suffix == ".parquet":
        _, pq = _pyarrow()
        table = pq.read_table(p)
        return {n: table.column(n).to_numpy() for n in table.column_names}
    with np.load(p, allow_pickle=False) as data:      # the units' entry is 0-d, a column 1-D
        return {n: data[n] for n in data.files if not (n == UNITS_KEY and data[n].ndim == 0)}


def read_units(path) -> dict[str, str]:
    """{column: unit} of a file that `write_columns` wrote with units ({} for one without)."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".csv":
        with open(p) as fh:
            first = fh.readline().rstrip("\n")
        if not first.startswith(UNITS_LINE):
            return {}
        pairs = (item.partition("=") for item in first[len(UNITS_LINE):].split(", "))
        return {n: u for n, _, u in pairs}
    if suffix == ".parquet":
        _, pq = _pyarrow()
        meta = pq.read_schema(p).metadata or {}
        text = meta.get(UNITS_KEY.encode())
        return json.loads(text) if text else {}
    with np.load(p, allow_pickle=False) as data:
        entry = data[UNITS_KEY] if UNITS_KEY in data.files else None
        return json.loads(str(entry)) if entry is not None and entry.ndim == 0 else {}


def write(path, names: list[str], table: np.ndarray, flag: str = "«save»",
          units: Mapping[str, str] | None = None) -> Path:
    """The table (rows: samples, columns: names) to path (write_columns)."""
    return write_columns(path, {n: table[:, i] for i, n in enumerate(names)}, flag, units)


def read(path) -> tuple[list[str], np.ndarray]:
    """(names, table) of a file that `write` wrote."""
    cols = read_columns(path)
    return list(cols), np.column_stack(list(cols.values()))
