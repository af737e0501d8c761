"""Reading a study's results back: rows, a pandas DataFrame, CSV and Parquet files.

Each row is a case's row of the database (:data:`~supcoord.study.store.COLUMNS`) with the
case's parameters also spread into columns of their own (``model``, ``route``, ``steps``,
``kinematics`` …; a parameter whose name is already a column, such as ``positioners`` or
``seed``, keeps the column) and ``extra`` as a dict (CSV: JSON text).

When a database holds the same case for several code versions, only the latest row of
each case (by start time) is kept unless ``versions="all"``; a ``skipped`` row never hides
a measured one.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..outputs import atomic_output, check_output
from .store import COLUMNS, ResultStore

__all__ = ["FORMATS", "export_results", "results_frame", "results_rows"]

FORMATS = ("csv", "parquet")


def results_rows(database: str | Path, *, study: Any = None, versions: str = "latest") -> list[dict[str, Any]]:
    """The rows of ``database`` (module docstring), ordered by series, size and seed.
    ``study``: only the rows of the study of that name, or of the cases of a
    :class:`~supcoord.study.spec.Study` (whichever study recorded them: studies that
    share a database share the cases they have in common)."""
    if versions not in ("latest", "all"):
        raise InputError("must be 'latest' or 'all'", value=versions, where="versions")
    with ResultStore(database, create=False) as store:
        rows = store.rows(study if isinstance(study, str) else None)
    if study is not None and not isinstance(study, str):
        wanted = {c.params_key for c in study.cases}
        rows = [r for r in rows if r["params_key"] in wanted]
    if versions == "latest":
        best: dict[str, dict[str, Any]] = {}
        for r in rows:
            key = r["params_key"] or r["key"]
            old = best.get(key)
            if old is None or _rank(r) > _rank(old):
                best[key] = r
        rows = [r for r in rows if best.get(r["params_key"] or r["key"]) is r]
    for r in rows:
        try:
            params = json.loads(r["params"]) if r.get("params") else {}
        except json.JSONDecodeError:
            params = {}
        for k, v in params.items():
            if k not in COLUMNS and k not in r:
                r[k] = v
    return rows


def _rank(r: dict[str, Any]) -> tuple:
    return (r.get("status") != "skipped", r.get("started") or "")


def results_frame(database: str | Path, *, study: Any = None, versions: str = "latest"):
    """The rows as a :class:`pandas.DataFrame` (one row per case, columns as in the module docstring)."""
    import pandas as pd

    rows = results_rows(database, study=study, versions=versions)
    columns = list(COLUMNS) + sorted({k for r in rows for k in r} - set(COLUMNS))
    return pd.DataFrame(rows, columns=columns)


def _flat(v: Any) -> Any:
    return json.dumps(v, sort_keys=True, default=str) if isinstance(v, (dict, list)) else v


def export_results(database: str | Path, out: str | Path, fmt: str | None = None, *, study: Any = None,
                   versions: str = "latest") -> int:
    """Write the rows to ``out`` as ``csv`` or ``parquet`` (default: from the suffix);
    returns the number of rows.  Parquet needs ``pyarrow`` (``pip install pyarrow``).

    ``out`` is written atomically and never over ``database`` or the study's file, nor
    through a link (:func:`supcoord.outputs.atomic_output`)."""
    if not isinstance(out, (str, os.PathLike)):
        raise InputError(f"must be a file name, got {out!r:.80}", value=out, where="out")
    out = Path(out)
    fmt = fmt or out.suffix.lstrip(".").lower()
    if fmt not in FORMATS:
        raise InputError(f"must be one of {', '.join(FORMATS)}", value=fmt, where="format")
    inputs = [database, *([study.path] if getattr(study, "path", None) else [])]
    check_output(out, inputs, "out")  # never over the database (also through a link), before reading it
    if fmt == "parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise InputError("Parquet export needs pyarrow: pip install pyarrow (or export --format csv)",
                             value="parquet", where="format") from None
    rows = results_rows(database, study=study, versions=versions)
    columns = list(COLUMNS) + sorted({k for r in rows for k in r} - set(COLUMNS))
    with atomic_output(out, inputs=inputs, what="out") as tmp:
        if fmt == "csv":
            with open(tmp, "w", newline="", encoding="utf-8") as f:
                w = csv.DictWriter(f, fieldnames=columns)
                w.writeheader()
                for r in rows:
                    w.writerow({k: _flat(r.get(k)) for k in columns})
        else:
            import pandas as pd

            frame = pd.DataFrame([{k: _flat(r.get(k)) for k in columns} for r in rows], columns=columns)
            frame.to_parquet(tmp, index=False)
    return len(rows)
