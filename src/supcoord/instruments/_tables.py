"""Reading and validating the packaged calibration tables (CSV files with a header row).

A table is read whole (bounded size), its header checked for the columns the caller
needs, and those columns parsed: numbers must be finite (or, where allowed, empty: NaN),
text must be non-empty.  Every problem is a :class:`~supcoord.errors.FormatError` whose
``where`` names the file (and line and column) and whose ``value`` is the offending value.

>>> t = parse_table("t.csv", "a,b\\n1,x\\n2.5,y\\n", numbers=("a",), texts=("b",))
>>> t["a"].tolist(), t["b"]
([1.0, 2.5], ('x', 'y'))
>>> parse_table("t.csv", "a\\n1\\n", numbers=("a", "zz"))
Traceback (most recent call last):
...
supcoord.errors.FormatError: t.csv: missing column 'zz' (columns: a)
"""

from __future__ import annotations

import csv
import io
import math
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import FormatError

__all__ = ["MAX_BYTES", "MAX_ROWS", "read_text", "parse_table"]

#: largest calibration file accepted (the biggest shipped one is ~125 kB)
MAX_BYTES = 2_000_000
#: most data rows accepted in one table (a wok has 561 holes)
MAX_ROWS = 5000


def read_text(name: str, data_dir: str | Path | None = None) -> str:
    """The text of calibration file ``name`` from the package data (or from ``data_dir``)."""
    if data_dir is None:
        ref = resources.files("supcoord.instruments").joinpath("data", "sdss_v", name)
    else:
        ref = Path(data_dir) / name
    try:
        with ref.open("rb") as fh:
            raw = fh.read(MAX_BYTES + 1)
    except OSError as exc:
        raise FormatError(f"cannot read calibration file: {exc.strerror or exc}", value=name, where=name) from None
    if len(raw) > MAX_BYTES:
        raise FormatError(f"file larger than {MAX_BYTES} bytes", value=len(raw), where=name)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise FormatError(f"not UTF-8 text (byte {exc.start})", value=exc.start, where=name) from None


def parse_table(
    file: str,
    text: str,
    *,
    numbers: tuple[str, ...] = (),
    texts: tuple[str, ...] = (),
    optional_numbers: tuple[str, ...] = (),
) -> dict[str, np.ndarray | tuple[str, ...]]:
    """Columns of a CSV text: ``numbers`` as float arrays, ``texts`` as tuples of strings.

    ``optional_numbers`` are numeric columns whose cells may be empty (NaN). The rows keep
    the file's order. Raises :class:`FormatError` for a missing column, a short row, a bad
    or non-finite number, an empty text cell, no rows or more than :data:`MAX_ROWS`.
    """
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = next(reader)
    except StopIteration:
        raise FormatError("empty file (no header row)", value="", where=file) from None
    except csv.Error as exc:
        raise FormatError(f"bad CSV header: {exc}", value=None, where=file) from None
    header = [h.strip() for h in header]
    index: dict[str, int] = {}
    for col in (*numbers, *texts, *optional_numbers):
        if col not in header:
            shown = ", ".join(h for h in header if h) or "none"
            raise FormatError(f"missing column {col!r} (columns: {shown})", value=col, where=file)
        index[col] = header.index(col)
    cells: dict[str, list] = {c: [] for c in index}
    line = 1
    try:
        for line, row in enumerate(reader, start=2):
            if not row or all(not c.strip() for c in row):
                continue
            if index and len(cells[next(iter(index))]) >= MAX_ROWS:
                raise FormatError(f"more than {MAX_ROWS} rows", value=line, where=file)
            for col, k in index.items():
                where = f"{file} line {line}, column {col}"
                if k >= len(row):
                    raise FormatError(f"row has {len(row)} cells, {col!r} is column {k + 1}", value=None, where=where)
                cells[col].append(_cell(row[k].strip(), col in texts, col in optional_numbers, where))
    except csv.Error as exc:
        raise FormatError(f"bad CSV: {exc}", value=None, where=f"{file} line {line}") from None
    if index and not cells[next(iter(index))]:
        raise FormatError("no data rows", value=0, where=file)
    out: dict[str, np.ndarray | tuple[str, ...]] = {}
    for col, vals in cells.items():
        out[col] = tuple(vals) if col in texts else np.asarray(vals, dtype=float)
    return out


def _cell(raw: str, text: bool, optional: bool, where: str) -> str | float:
    """One stripped cell: a non-empty text, or a finite number (NaN where ``optional`` and empty)."""
    if text:
        if not raw:
            raise FormatError("empty value", value=raw, where=where)
        return raw
    if not raw and optional:
        return math.nan
    try:
        val = float(raw)
    except ValueError:
        raise FormatError(f"not a number: {raw[:40]!r}", value=raw[:40], where=where) from None
    if not math.isfinite(val):
        raise FormatError(f"not a finite number: {raw[:40]!r}", value=raw[:40], where=where)
    return val
