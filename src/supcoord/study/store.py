"""The results database: one SQLite file, one row per case, committed as each case ends.

Why SQLite (from the standard library) rather than DuckDB: measured on this project's
machines (``benchmarks/bench_study_db.py``, ``benchmarks/results/study_db.md``),
committing one row takes 0.6 to 8 ms in SQLite with a full ``fsync`` (the machine's load
decides) and 9 to 11 ms in DuckDB, and the queries a study makes on 10^4 rows take
milliseconds in both (DuckDB's scans are faster, which no study needs: its cases take
seconds); SQLite needs no dependency and is read by every tool.  The file uses SQLite's default rollback journal
(one file, nothing beside it once closed) with ``synchronous=FULL``: a committed case
survives a crash of the machine.

Tables:

- ``cases``: one row per case and code version (:data:`COLUMNS`); ``key`` identifies the
  case (parameters and version, :class:`~supcoord.study.spec.Case`), ``params_key`` the
  parameters alone, ``params`` is their canonical JSON and ``extra`` the kind's other
  numbers as JSON.  A case run again (after a time-out with a larger limit, say)
  replaces its row;
- ``runs``: one row per ``run`` of a study: when, where, how many workers, how many cases
  it ran and how it ended (finished or interrupted), with its wall-clock seconds.

The file carries :data:`APPLICATION_ID` (``PRAGMA application_id``).  Opening refuses,
before changing anything, a SQLite file of another application (one-line
:class:`~supcoord.errors.InputError`) and a corrupt one (``PRAGMA quick_check``); a
database written before the id existed is recognised by its tables and gains the id when
it is next written.  Readers open the file read-only.
"""

from __future__ import annotations

import contextlib
import json
import os
import sqlite3
from collections.abc import Iterable, Iterator
from contextlib import closing
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..outputs import check_output

__all__ = ["APPLICATION_ID", "COLUMNS", "RUN_COLUMNS", "ResultStore"]

#: SQLite's ``PRAGMA application_id`` of a supcoord results database ("supc" in ASCII)
APPLICATION_ID = 0x73757063

#: column -> SQL type of the ``cases`` table (docs/study.md explains each)
COLUMNS: dict[str, str] = {
    "key": "TEXT PRIMARY KEY", "params_key": "TEXT", "study": "TEXT", "kind": "TEXT", "series": "TEXT",
    "size": "INTEGER", "positioners": "INTEGER", "seed": "INTEGER", "params": "TEXT", "version": "TEXT",
    "machine": "TEXT", "cpu": "TEXT", "load": "REAL", "started": "TEXT", "status": "TEXT", "message": "TEXT",
    "seconds": "REAL", "wall_seconds": "REAL", "cpu_seconds": "REAL", "peak_rss_mb": "REAL", "bdd_nodes": "INTEGER",
    "states": "TEXT", "states_log10": "REAL", "verdict": "TEXT", "makespan": "INTEGER", "lower_bound": "INTEGER",
    "time_limit": "REAL", "memory_limit_mb": "REAL", "worker": "TEXT", "run": "INTEGER", "extra": "TEXT",
}
RUN_COLUMNS: dict[str, str] = {
    "run": "INTEGER PRIMARY KEY AUTOINCREMENT", "study": "TEXT", "started": "TEXT", "finished": "TEXT",
    "version": "TEXT", "machine": "TEXT", "cpu": "TEXT", "workers": "INTEGER", "scheduler": "TEXT",
    "total": "INTEGER", "pending": "INTEGER", "ran": "INTEGER", "failed": "INTEGER", "skipped": "INTEGER",
    "wall_seconds": "REAL", "ended": "TEXT", "command": "TEXT",
}


class ResultStore:
    """The database at ``path`` (created with its tables on first use).

    >>> import tempfile, os
    >>> path = os.path.join(tempfile.mkdtemp(), "r.sqlite")
    >>> with ResultStore(path) as db:
    ...     db.record({"key": "k1", "study": "s", "status": "ok", "seconds": 1.5, "extra": {"rank": 3}})
    ...     db.rows()[0]["seconds"], db.rows()[0]["extra"]
    (1.5, {'rank': 3})
    """

    def __init__(self, path: str | Path, *, create: bool = True, inputs: Iterable[str | Path | None] = ()):
        if not isinstance(path, (str, os.PathLike)) or not os.fspath(path):
            raise InputError(f"must be a file name, got {path!r:.80}", value=path, where="database")
        self.path = Path(path)
        where = str(path)
        if not create and not self.path.is_file():
            raise InputError("no results database here yet (run the study first)", value=where, where=where)
        if create:  # written in place: never an input, a link, a directory or a FIFO
            check_output(self.path, inputs, "results database")
        try:
            if create:
                self.con = sqlite3.connect(str(self.path), isolation_level=None, timeout=30)
            else:  # read only: show/export/plot change nothing
                self.con = sqlite3.connect(self.path.absolute().as_uri() + "?mode=ro", uri=True,
                                           isolation_level=None, timeout=30)
        except sqlite3.Error as exc:
            raise InputError(f"cannot open the results database ({exc})", value=where, where=where) from None
        try:
            self.empty = fresh = self._identify(where)
            if create:
                self.con.execute("PRAGMA synchronous=FULL")
                self._create()
                self.empty = False
                if fresh or self.con.execute("PRAGMA application_id").fetchone()[0] != APPLICATION_ID:
                    self.con.execute(f"PRAGMA application_id={APPLICATION_ID}")
        except sqlite3.DatabaseError as exc:
            self.con.close()
            raise InputError(f"not a results database ({exc})", value=where, where=where) from None
        except InputError:
            self.con.close()
            raise

    def _identify(self, where: str) -> bool:
        """Refuse (before any change) a file that is not a supcoord results database or is
        corrupt; True for an empty database (a new file).  A database is supcoord's when it
        carries :data:`APPLICATION_ID`, or (written before the id existed) holds only the
        ``cases`` and ``runs`` tables with columns of :data:`COLUMNS` / :data:`RUN_COLUMNS`."""
        app = self.con.execute("PRAGMA application_id").fetchone()[0]
        try:
            check = [r[0] for r in self.con.execute("PRAGMA quick_check")]
        except sqlite3.DatabaseError as exc:
            check = [str(exc)]
        if check != ["ok"]:
            raise InputError(f"the results database is corrupt (SQLite's quick_check: {'; '.join(check[:3])}); "
                             "restore a copy, or give another database", value=where, where=where)
        tables = {r[0] for r in self.con.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        if app == APPLICATION_ID:
            return False
        if app == 0 and not tables:
            return True
        layout = {"cases": COLUMNS, "runs": RUN_COLUMNS}
        ours = app == 0 and "cases" in tables and tables <= {*layout, "sqlite_sequence"} and all(
            {r[1] for r in self.con.execute(f"PRAGMA table_info({t})")} <= set(layout[t]) for t in tables & set(layout))
        if not ours:
            shown = ", ".join(sorted(tables)[:5]) or "none"
            raise InputError(f"is a SQLite database but not a supcoord results database (application id {app}, "
                             f"tables: {shown}); give another database file",
                             value=where, where=where)
        return False

    def _create(self) -> None:
        cols = ", ".join(f"{c} {t}" for c, t in COLUMNS.items())
        self.con.execute(f"CREATE TABLE IF NOT EXISTS cases ({cols})")
        self.con.execute(f"CREATE TABLE IF NOT EXISTS runs ({', '.join(f'{c} {t}' for c, t in RUN_COLUMNS.items())})")
        have = {r[1] for r in self.con.execute("PRAGMA table_info(cases)")}
        for c, t in COLUMNS.items():  # a database of an older layout gains the new columns
            if c not in have:
                self.con.execute(f"ALTER TABLE cases ADD COLUMN {c} {t.replace(' PRIMARY KEY', '')}")

    def __enter__(self) -> ResultStore:  # noqa: PYI034
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.con.close()

    # -- writing -------------------------------------------------------------------------

    @contextlib.contextmanager
    def _transaction(self) -> Iterator[None]:
        """BEGIN … COMMIT (rolled back on an error); a failed write (a full disk, a file-size
        limit, a read-only file system) is an :class:`InputError` naming the database."""
        try:
            with self.con:
                self.con.execute("BEGIN")
                yield
        except sqlite3.Error as exc:
            raise InputError(f"cannot write the results database ({exc})", value=str(self.path),
                             where=str(self.path)) from None

    def record(self, row: dict[str, Any]) -> None:
        """Insert or replace one case's row and commit it (one transaction)."""
        values = {c: row.get(c) for c in COLUMNS}
        if not isinstance(values["extra"], (str, type(None))):
            values["extra"] = json.dumps(values["extra"], default=str, sort_keys=True)
        names = ", ".join(values)
        with self._transaction():
            self.con.execute(f"INSERT OR REPLACE INTO cases ({names}) VALUES ({', '.join('?' * len(values))})",
                             [_plain(v) for v in values.values()])

    def forget(self, keys: Iterable[str]) -> None:
        """Delete the rows of ``keys`` (cases recorded as skipped that are due again)."""
        with self._transaction():
            self.con.executemany("DELETE FROM cases WHERE key = ?", [(k,) for k in keys])

    def start_run(self, **fields: Any) -> int:
        with self._transaction():
            cur = self.con.execute(f"INSERT INTO runs ({', '.join(fields)}) VALUES ({', '.join('?' * len(fields))})",
                                   [_plain(v) for v in fields.values()])
        return int(cur.lastrowid)

    def finish_run(self, run: int, **fields: Any) -> None:
        with self._transaction():
            self.con.execute(f"UPDATE runs SET {', '.join(f'{k} = ?' for k in fields)} WHERE run = ?",
                             [*map(_plain, fields.values()), run])

    # -- reading -------------------------------------------------------------------------

    def finished(self) -> list[tuple[str, str, str, float | None, float | None, str]]:
        """``(key, params_key, status, time limit, memory limit MB, started)`` of every recorded case."""
        if self.empty:
            return []
        return list(self.con.execute("SELECT key, params_key, status, time_limit, memory_limit_mb, started FROM cases"))

    def rows(self, study: str | None = None) -> list[dict[str, Any]]:
        """Every case row (``extra`` parsed), ordered by series, size and seed."""
        if self.empty:
            return []
        sql = "SELECT * FROM cases" + (" WHERE study = ?" if study else "")
        with closing(self.con.execute(sql + " ORDER BY series, size, seed, started", (study,) if study else ())) as cur:
            names = [d[0] for d in cur.description]
            out = [dict(zip(names, r)) for r in cur]
        for r in out:
            r["extra"] = json.loads(r["extra"]) if r.get("extra") else {}
        return out

    def runs(self) -> list[dict[str, Any]]:
        if self.empty:
            return []
        with closing(self.con.execute("SELECT * FROM runs ORDER BY run")) as cur:
            names = [d[0] for d in cur.description]
            return [dict(zip(names, r)) for r in cur]


def _plain(v: Any) -> Any:
    """SQLite's types: numpy scalars as Python numbers, containers as JSON, huge ints as text."""
    if hasattr(v, "item") and callable(v.item):
        v = v.item()
    if isinstance(v, bool):
        return int(v)
    if isinstance(v, int) and abs(v) >= 2**63:
        return str(v)
    if isinstance(v, (dict, list, tuple)):
        return json.dumps(v, default=str, sort_keys=True)
    return v
