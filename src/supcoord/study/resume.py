"""Resuming a study: which of its cases the results database already settles.

A case is **done** when the database holds its key (same parameters, same code version)
with status ``ok``, ``error`` or ``crashed``, or ``timeout``/``out-of-memory`` under a
limit at least as large as the one asked now (so raising a limit re-runs exactly the
cases that ran out of it); ``retry`` names statuses to run again (``crashed``, say, after a
fix; :data:`~.isolate.FAILED`: every failure).  A case
whose Dask worker died on every try (``KilledWorker``: a node that went away, a job that
ended) is recorded as ``lost`` and is never done: the next run runs it again.

:func:`pending` is what :func:`~.execute.run_study` runs; :func:`records` and :func:`is_done`
are what ``supcoord study show`` counts.
"""

from __future__ import annotations

from collections.abc import Iterable

from .spec import Case, Study
from .store import ResultStore

__all__ = ["Record", "is_done", "pending", "records"]

#: a recorded ``(status, time limit in s, memory limit in MB)``
Record = tuple[str, float | None, float | None]


def is_done(record: Record | None, case: Case, retry: Iterable[str] = ()) -> bool:
    """Whether a recorded ``(status, time limit, memory limit)`` settles ``case`` (module docstring)."""
    if record is None:
        return False
    status, limit, memory = record
    if status == "ok":
        return True
    if status in retry or status in ("skipped", "lost"):
        return False
    if status == "timeout":
        return limit is not None and limit >= case.time_limit
    if status == "out-of-memory":
        return case.memory_limit_mb is not None and (memory is None or memory >= case.memory_limit_mb)
    return status in ("error", "crashed")


def records(study: Study, store: ResultStore, version: str, any_version: bool = False) -> dict[str, Record]:
    """``params_key -> (status, time limit, memory limit)`` of the study's recorded cases:
    the row of ``version``, or with ``any_version`` the best row of any version (an ``ok``
    one, else the latest)."""
    by_key: dict[str, Record] = {}
    best: dict[str, tuple[bool, str, Record]] = {}
    for key, params_key, status, limit, memory, started in store.finished():
        by_key[key] = (status, limit, memory)
        rank = (status == "ok", started or "", (status, limit, memory))
        if params_key and (params_key not in best or rank[:2] > best[params_key][:2]):
            best[params_key] = rank
    if any_version:
        return {c.params_key: best[c.params_key][2] for c in study.cases if c.params_key in best}
    return {c.params_key: by_key[c.key(version)] for c in study.cases if c.key(version) in by_key}


def pending(study: Study, store: ResultStore, version: str, retry: Iterable[str] = (),
            any_version: bool = False) -> list[Case]:
    """The cases of ``study`` not done in ``store`` for ``version`` (or for any version), smallest first."""
    found = records(study, store, version, any_version)
    todo = [c for c in study.cases if not is_done(found.get(c.params_key), c, tuple(retry))]
    return sorted(todo, key=lambda c: (c.size if c.size is not None else 0, c.block))
