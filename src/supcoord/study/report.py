"""Progress of a running study and summaries of its results, as text.

- :class:`StudyProgress`: one line per finished case, ``[ 12/40] 10 ok, 2 failed, 28
  left | 4.1 cases/min | about 6m50s left | <the case>: <status> <seconds> s, <MB> MB``.
  The throughput counts the cases finished by this run per minute of this run; the time
  left is the cases left divided by that throughput (an estimate: cases differ in size);
- :func:`summary_rows`: per series and size, the number of cases per status and the
  median/maximum seconds, peak memory and BDD nodes (what ``supcoord study show`` prints);
- :func:`markdown_table`: rows as a Markdown table.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Iterable
from typing import Any

from .isolate import FAILED

__all__ = ["StudyProgress", "duration", "markdown_table", "summary_rows"]


def duration(seconds: float) -> str:
    """``42s``, ``6m50s``, ``2h05m``."""
    s = round(seconds)
    if s < 60:
        return f"{s}s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{(s % 3600) // 60:02d}m"


class StudyProgress:
    """Counts and throughput of a run; writes its lines to ``write`` (None: silent)."""

    def __init__(self, total: int, already: int, write: Callable[[str], None] | None = print,
                 already_failed: int = 0):
        self.total, self.already, self.write = total, already, write
        self.already_failed = already_failed
        self.ok = self.failed = self.skipped = 0
        self.started = time.perf_counter()

    @property
    def count(self) -> int:
        """Cases this run has finished (skipped ones included)."""
        return self.ok + self.failed + self.skipped

    def line(self, text: str) -> None:
        if self.write is not None:
            self.write(text)

    def rate(self) -> float:
        """Cases finished by this run per minute of this run."""
        elapsed = time.perf_counter() - self.started
        return 60.0 * (self.ok + self.failed) / elapsed if elapsed > 0 else 0.0

    def finished_line(self, case: Any, row: dict[str, Any]) -> str:
        done = self.already + self.count
        left = self.total - done
        rate = self.rate()
        eta = f"about {duration(60.0 * left / rate)} left" if rate > 0 and left else ("done" if not left else "…")
        what = row["status"]
        if row.get("status") == "ok":
            what = f"{row.get('verdict') or 'ok'}, {row.get('seconds') or 0:.2f} s"
            if row.get("peak_rss_mb"):
                what += f", {row['peak_rss_mb']:.0f} MB"
        elif row.get("message"):
            what += f" ({row['message'][:100]})"
        width = len(str(self.total))
        ok, failed = self.already - self.already_failed + self.ok, self.already_failed + self.failed
        return (f"[{done:>{width}}/{self.total}] {ok} ok, {failed} failed, {left} left | "
                f"{rate:.1f} cases/min | {eta} | {case.describe()}: {what}")

    def finished(self, case: Any, row: dict[str, Any]) -> None:
        status = row.get("status")
        if status == "ok":
            self.ok += 1
        elif status == "skipped":
            self.skipped += 1
        else:
            self.failed += 1
        self.line(self.finished_line(case, row))

    def done(self, summary: Any) -> None:
        how = "interrupted" if summary.interrupted else "finished"
        statuses = ", ".join(f"{n} {s}" for s, n in sorted(summary.statuses.items())) or "nothing"
        tail = (f"; {summary.left} left: run again to resume" if summary.left else "")
        self.line(f"{summary.study}: {how} after {duration(summary.wall_seconds)}: ran {summary.ran} "
                  f"({statuses}){tail}")


def _median(values: Iterable[float | None]) -> float | None:
    vs = [v for v in values if v is not None]
    return statistics.median(vs) if vs else None


def summary_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per series and size: counts per status, median and max seconds, max peak MB and BDD nodes."""
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault((r["series"], r["size"] if r["size"] is not None else -1), []).append(r)
    out = []
    for (series, size), rs in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        ok = [r for r in rs if r["status"] == "ok"]
        verdicts: dict[str, int] = {}
        for r in ok:
            verdicts[r.get("verdict") or "ok"] = verdicts.get(r.get("verdict") or "ok", 0) + 1
        out.append({
            "series": series, "size": None if size == -1 else size, "cases": len(rs), "ok": len(ok),
            "failed": sum(r["status"] in FAILED for r in rs), "skipped": sum(r["status"] == "skipped" for r in rs),
            "verdicts": ", ".join(f"{n} {v}" for v, n in sorted(verdicts.items())),
            "median s": _median(r["seconds"] for r in ok), "max s": max((r["seconds"] for r in ok if r["seconds"] is not None), default=None),
            "max MB": max((r["peak_rss_mb"] for r in rs if r.get("peak_rss_mb") is not None), default=None),
            "max BDD nodes": max((r["bdd_nodes"] for r in ok if r.get("bdd_nodes") is not None), default=None),
            "median makespan/LB": _median(r["makespan"] / max(1, r["lower_bound"]) for r in ok
                                          if r.get("makespan") is not None and r.get("lower_bound") is not None),
        })
    return out


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.3g}" if abs(v) < 100 else f"{v:,.0f}"
    if isinstance(v, int):
        return f"{v:,}"
    return str(v)


def markdown_table(rows: list[dict[str, Any]], columns: list[str] | None = None) -> str:
    if not rows:
        return "(no rows)"
    columns = columns or list(rows[0])
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    lines += ["| " + " | ".join(_cell(r.get(c)) for c in columns) + " |" for r in rows]
    return "\n".join(lines)
