"""Which embedded database for study results: SQLite (standard library) or DuckDB.

A study commits one row per case when the case finishes, then reads the whole table for
``show``, ``export`` and the plots.  This measures both on a table of the study's shape
(about 30 columns: parameters as JSON, code version, machine, status, seconds, memory,
BDD nodes, verdict, makespan …):

- **insert + commit** of one row, one transaction per row (what ``supcoord study run``
  does), median and 95th percentile over ``--commits`` rows, in a database that already
  holds ``--rows`` rows;
- **queries on ``--rows`` rows**: the keys of the finished cases (what a resumed run
  reads), a grouped median-free aggregate (count, mean, max per series and size, what
  ``show`` prints), and the whole table into a pandas DataFrame (export and plots);
- the file size.

SQLite runs in two modes: its default rollback journal with ``synchronous=FULL``, and
write-ahead logging with ``synchronous=NORMAL`` (committed rows survive a crash of the
process; the last commits may be lost only on a power failure).  Writes
``results/study_db.md``.

    python benchmarks/bench_study_db.py                 # 10^4 rows, 500 commits
    python benchmarks/bench_study_db.py --rows 1000 --commits 100 --out /tmp/db.md
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import statistics
import sys
import tempfile
import time
from datetime import UTC, datetime

HERE = os.path.dirname(os.path.abspath(__file__))
COLUMNS = [("key", "TEXT PRIMARY KEY"), ("params_key", "TEXT"), ("study", "TEXT"), ("kind", "TEXT"),
           ("series", "TEXT"), ("params", "TEXT"), ("size", "INTEGER"), ("positioners", "INTEGER"),
           ("seed", "INTEGER"), ("version", "TEXT"), ("machine", "TEXT"), ("cpu", "TEXT"), ("load", "DOUBLE"),
           ("started", "TEXT"), ("status", "TEXT"), ("message", "TEXT"), ("seconds", "DOUBLE"),
           ("wall_seconds", "DOUBLE"), ("cpu_seconds", "DOUBLE"), ("peak_rss_mb", "DOUBLE"),
           ("bdd_nodes", "BIGINT"), ("states", "TEXT"), ("states_log10", "DOUBLE"), ("verdict", "TEXT"),
           ("makespan", "INTEGER"), ("lower_bound", "INTEGER"), ("time_limit", "DOUBLE"),
           ("memory_limit_mb", "DOUBLE"), ("worker", "TEXT"), ("result", "TEXT")]
NAMES = [c for c, _ in COLUMNS]
QUERIES = {
    "finished keys (resume)": "SELECT key, status, time_limit, memory_limit_mb FROM cases",
    "per series and size (show)": ("SELECT series, size, count(*), avg(seconds), max(seconds), max(peak_rss_mb), "
                                   "max(bdd_nodes) FROM cases GROUP BY series, size ORDER BY series, size"),
}


def row(i: int) -> tuple:
    r = random.Random(i)
    series = r.choice(["paper literal modular", "paper coupled monolithic", "solve rotary local",
                       "solve alpha-beta local", "supcon dining_philosophers"])
    size = r.choice([7, 19, 37, 61, 91, 127, 169, 271, 397, 547])
    params = json.dumps({"kind": series.split()[0], "positioners": size, "seed": i % 5, "steps": 12}, sort_keys=True)
    return (f"{i:040x}", f"{i // 2:040x}", "bench", series.split()[0], series, params, size, size, i % 5,
            "0.2.0+g3dfed15", "host", "Intel(R) Xeon(R) CPU @ 2.20GHz", r.random() * 2,
            "2026-01-01T00:00:00+00:00", r.choice(["ok", "ok", "ok", "timeout"]), "", r.random() * 100,
            r.random() * 100, r.random() * 100, 100 + r.random() * 1000, r.randrange(10**7), str(r.randrange(10**12)),
            r.random() * 100, "complete", r.randrange(40), r.randrange(20), 600.0, 6144.0, "tcp://127.0.0.1:1",
            json.dumps({"windows": r.randrange(100)}))


def sqlite_db(path: str, wal: bool):
    import sqlite3

    con = sqlite3.connect(path, isolation_level=None)
    if wal:
        con.execute("PRAGMA journal_mode=WAL")
        con.execute("PRAGMA synchronous=NORMAL")
    else:
        con.execute("PRAGMA synchronous=FULL")
    return con


def duckdb_db(path: str):
    import duckdb

    return duckdb.connect(path)


def measure(name: str, connect, rows: int, commits: int) -> dict:
    import pandas as pd

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "study.db")
        con = connect(path)
        con.execute(f"CREATE TABLE cases ({', '.join(f'{c} {t}' for c, t in COLUMNS)})")
        marks = ", ".join("?" * len(COLUMNS))
        insert = f"INSERT OR REPLACE INTO cases ({', '.join(NAMES)}) VALUES ({marks})"
        con.execute("BEGIN")  # the bulk of the table, one transaction (not timed per row)
        con.executemany(insert, [row(i) for i in range(rows - commits)])
        con.execute("COMMIT")
        latencies = []
        for i in range(rows - commits, rows):  # what a study does: one transaction per finished case
            values = row(i)
            t0 = time.perf_counter()
            con.execute("BEGIN")
            con.execute(insert, values)
            con.execute("COMMIT")
            latencies.append(time.perf_counter() - t0)
        out = {"database": name, "commit median ms": statistics.median(latencies) * 1e3,
               "commit p95 ms": sorted(latencies)[int(0.95 * len(latencies))] * 1e3}
        for label, sql in QUERIES.items():
            best = min(_timed(lambda q=sql: con.execute(q).fetchall()) for _ in range(5))
            out[f"{label} ms"] = best * 1e3
        if name.startswith("DuckDB"):
            frame = lambda: con.execute("SELECT * FROM cases").df()
        else:
            frame = lambda: pd.read_sql_query("SELECT * FROM cases", con)
        out["whole table to DataFrame ms"] = min(_timed(frame) for _ in range(3)) * 1e3
        assert len(frame()) == rows
        con.close()
        out["file MB"] = sum(os.path.getsize(os.path.join(tmp, f)) for f in os.listdir(tmp)) / 2**20
    return out


def _timed(f) -> float:
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def _cpu() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            return next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        return platform.machine()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=10_000)
    ap.add_argument("--commits", type=int, default=500)
    ap.add_argument("--out", default=os.path.join(HERE, "results", "study_db.md"))
    args = ap.parse_args(argv)
    import sqlite3

    import duckdb

    results = [measure("SQLite (rollback journal, synchronous=FULL)", lambda p: sqlite_db(p, False), args.rows, args.commits),
               measure("SQLite (WAL, synchronous=NORMAL)", lambda p: sqlite_db(p, True), args.rows, args.commits),
               measure("DuckDB", duckdb_db, args.rows, args.commits)]
    keys = list(results[0])
    lines = ["# Study results database: SQLite or DuckDB (`benchmarks/bench_study_db.py`)", "",
             "- command: `" + " ".join(["python benchmarks/bench_study_db.py", *(argv if argv is not None else sys.argv[1:])]) + "`",
             f"- date: {datetime.now(UTC):%Y-%m-%d %H:%M} UTC; load {' / '.join(f'{x:.2f}' for x in os.getloadavg())}",
             (f"- machine: {_cpu()}, nproc {os.cpu_count()}, Python "
              f"{platform.python_version()}, SQLite {sqlite3.sqlite_version}, DuckDB {duckdb.__version__}"),
             (f"- table: {len(COLUMNS)} columns of a study's row; {args.rows} rows; {args.commits} single-row "
              "commits timed at the end (queries: best of 5, DataFrame: best of 3)"), "",
             "| " + " | ".join(keys) + " |", "|---" + "|---:" * (len(keys) - 1) + "|"]
    for r in results:
        lines.append("| " + " | ".join(r[k] if isinstance(r[k], str) else f"{r[k]:.2f}" for k in keys) + " |")
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
