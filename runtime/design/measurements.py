"""The measurements a fit is made to (runtime/design/fit.py): one `Row` per measured quantity (its
SI unit in QUANTITIES), value, standard deviation and the scene keys it was measured at; read from a
--fit CSV (`read_rows`: header quantity,value,sigma[,overrides], a byte-order mark, CRLF and a
size limit handled) or given as a list through the API, and checked one way for both (`check_row`).
"""
from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

from levitron.runtime.errors import UserError
from levitron.runtime.ui.validate import number_text, real

QUANTITIES = {"z_s": "m", "stiffness": "N/m", "sigma_lo": "rad/s", "sigma_hi": "rad/s",
              "z_c": "m", "max_mass": "kg"}


@dataclass(frozen=True)
class Row:
    """One measurement: quantity (QUANTITIES, SI unit), value, sigma (its standard deviation),
    overrides (scene key -> value for this row)."""

    quantity: str
    value: float
    sigma: float
    overrides: tuple[tuple[str, float], ...] = ()


COLUMNS = ("quantity", "value", "sigma", "overrides")
MIN_SIGMA = 1e-150      # the weighted residuals (value / sigma) are squared: stay in double range
MAX_ROWS = 10_000
MAX_BYTES = 16 * 2**20      # bytes of a --fit file read at most: MAX_ROWS rows of 1.6 kB


def check_row(row, where: str) -> Row:
    """The one check of a measurement, for CSV rows (read_rows) and the API's Row lists (fit):
    a known quantity, a finite value, a finite sigma >= MIN_SIGMA, overrides of distinct scene keys
    to finite numbers."""
    if not isinstance(row, Row):
        raise UserError(f"{where}: {row!r} is not a runtime.design.measurements.Row (quantity, value, sigma, "
                        "overrides)")
    if row.quantity not in QUANTITIES:
        raise UserError(f"{where}: quantity {row.quantity!r}: use one of {', '.join(QUANTITIES)}")
    value = real(row.value, f"{where}: value")
    if value <= 0:      # every QUANTITY is positive: a height above the plate z = 0, a stable
        # stiffness U'' > 0 (thesis 3.3.3), the spin interval's ends, z_c, the largest mass
        raise UserError(f"{where}: {row.quantity} = {value:g} must be positive: check the sign "
                        "and the units")
    sigma = real(row.sigma, f"{where}: sigma", positive=True)
    if sigma < MIN_SIGMA or abs(value) / sigma > 1 / MIN_SIGMA:
        raise UserError(f"{where}: sigma = {sigma:g} is too small for value {value:g} (the squared "
                        f"residuals would leave double range): give sigma >= {MIN_SIGMA:g} and "
                        f"|value| / sigma <= {1 / MIN_SIGMA:g}")
    over, seen = [], set()
    for item in row.overrides:
        if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str)):
            raise UserError(f"{where}: override {item!r}: give (scene key, number) pairs")
        key = item[0].strip()
        if key in seen:
            raise UserError(f"{where}: the override {key} is given twice: give each key once")
        seen.add(key)
        over.append((key, real(item[1], f"{where}: override {key}")))
    return Row(row.quantity, value, sigma, tuple(over))


def check_rows(rows, where: str = "«fit»") -> list[Row]:
    """check_row of every row; at least one row, at most MAX_ROWS."""
    if isinstance(rows, (str, bytes)) or not hasattr(rows, "__iter__"):
        raise UserError(f"{where}: give a CSV path or a list of runtime.design.measurements.Row")
    rows = list(rows)
    if not rows:
        raise UserError(f"{where}: no data rows")
    if len(rows) > MAX_ROWS:
        raise UserError(f"{where}: {len(rows)} rows is too many (at most {MAX_ROWS})")
    return [check_row(r, f"{where} row {i + 1}") for i, r in enumerate(rows)]


def _number(text: str) -> float:
    """A CSV cell's number (runtime/ui/validate.py number_text: no '_', ASCII digits only)."""
    return number_text(text)


def read_rows(path: str | Path) -> list[Row]:
    """The rows of a CSV file with header quantity,value,sigma[,overrides]; overrides are
    `key=value` pairs separated by ';'. UserError naming the line on any problem: an unknown or
    repeated column, a line with more fields than the header, a key overridden twice."""
    try:
        with open(path, "rb") as fh:                # at most MAX_BYTES (/dev/zero, a huge file: refused)
            data = fh.read(MAX_BYTES + 1)
        if len(data) > MAX_BYTES:
            raise UserError(f"«fit» {path}: longer than {MAX_BYTES // 2**20} MB, more than a file of "
                            f"{MAX_ROWS} rows holds: give the CSV of the measurements")
        text = data.decode("utf-8-sig")             # a spreadsheet's byte-order mark
    except (OSError, UnicodeDecodeError) as exc:
        raise UserError(f"«fit» {path}: cannot be read ({exc}): give a CSV file") from None
    lines = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    try:
        table = list(csv.reader(line for _, line in lines))
    except csv.Error as exc:
        raise UserError(f"«fit» {path}: not a CSV file ({exc})") from None
    header = [h.strip() for h in table[0]] if table else []
    if not {"quantity", "value", "sigma"} <= set(header):
        raise UserError(f"«fit» {path}: the header must name quantity,value,sigma[,overrides]")
    unknown = [h for h in header if h not in COLUMNS]
    if unknown:
        raise UserError(f"«fit» {path}: unknown column {unknown[0]!r}: the columns are "
                        f"{','.join(COLUMNS)} (put per-row scene keys into overrides: key=value;...)")
    repeated = sorted({h for h in header if header.count(h) > 1})
    if repeated:
        raise UserError(f"«fit» {path}: the column {repeated[0]!r} appears twice in the header")
    rows = []
    for (n, _), fields in zip(lines[1:], table[1:]):
        if len(fields) > len(header):
            raise UserError(f"«fit» {path} line {n}: {len(fields)} fields for {len(header)} columns: "
                            "remove the extra ones (a ',' inside overrides? separate them by ';')")
        rec = dict(zip(header, (f.strip() for f in fields)))
        try:
            value, sigma = _number(rec.get("value", "")), _number(rec.get("sigma", ""))
        except ValueError:
            raise UserError(f"«fit» {path} line {n}: value and sigma must be numbers") from None
        over = []
        for item in filter(None, (s.strip() for s in rec.get("overrides", "").split(";"))):
            key, eq, v = item.partition("=")
            try:
                if not eq:
                    raise ValueError(item)
                over.append((key.strip(), _number(v)))
            except ValueError:
                raise UserError(f"«fit» {path} line {n}: override {item!r}: write key=number") from None
        rows.append(check_row(Row(rec.get("quantity", ""), value, sigma, tuple(over)),
                              f"«fit» {path} line {n}"))
    return check_rows(rows, f"«fit» {path}")
