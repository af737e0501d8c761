"""Running a study: the cases not yet done, on Dask workers, each committed as it ends.

:func:`run_study` reads the database, keeps the cases that are not **done** (below),
orders them by size (small first, so the early rows already draw every curve and a
``skip_larger`` rule can apply), and hands them to an executor:

- ``workers >= 1`` (default 2) and no scheduler: an embedded ``dask.distributed``
  ``LocalCluster`` of that many worker *processes*, one thread each;
- ``scheduler="tcp://host:8786"``: an existing Dask cluster (``dask-jobqueue`` on Slurm,
  ``dask-ssh``, a ``dask scheduler`` you started); its workers must run the same code
  version (checked before anything runs);
- ``workers=0``: no Dask; the cases run one after another from this process.

In every case each case runs in a process of its own with its time and memory limits
(:mod:`.isolate`).  At most two cases per worker are handed out at a time, and a case
of a ``skip_larger`` block waits until the smaller cases of its series have finished, so
the rule sees their failures before the larger cases are sent; a Ctrl-C
(``KeyboardInterrupt``; also SIGTERM, which Slurm sends at the end of a job) stops the
cases that are running, kills their processes and leaves the finished ones committed.

A case is **done** as :mod:`.resume` decides; the others run.
"""

from __future__ import annotations

import collections
import contextlib
import os
import signal
import threading
import time
import uuid
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from ..errors import InputError
from ..progress import summary_html, summary_repr
from .isolate import FAILED, execute
from .machine import code_version, cpu_model, machine
from .report import StudyProgress
from .resume import is_done, pending, records
from .spec import Case, Study
from .store import ResultStore

__all__ = ["DEFAULT_WORKERS", "RunSummary", "run_study"]

DEFAULT_WORKERS = 2


@dataclass
class RunSummary:
    """What one :func:`run_study` did: counts of the study's cases and of this run's outcomes."""

    study: str
    database: str
    version: str
    total: int
    pending: int
    ran: int = 0
    statuses: dict[str, int] = field(default_factory=dict)
    wall_seconds: float = 0.0
    interrupted: bool = False
    workers: int = 0
    run: int | None = None
    #: the first case of this run that crashed: ``"series, parameters: message"`` (None: none)
    first_crash: str | None = None

    @property
    def failed(self) -> int:
        return sum(self.statuses.get(s, 0) for s in FAILED)

    @property
    def left(self) -> int:
        """Cases this run did not get to (it was interrupted)."""
        return self.pending - self.ran

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: the study, its cases, what this run did, the outcomes."""
        out: dict[str, Any] = {"study": self.study, "cases": self.total, "pending": self.pending, "ran": self.ran,
                               "failed": self.failed, "wall_seconds": round(self.wall_seconds, 1),
                               "interrupted": self.interrupted, "database": self.database}
        out.update({f"n_{k}": v for k, v in sorted(self.statuses.items())})
        return out

    def __repr__(self) -> str:
        return summary_repr("RunSummary", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("RunSummary", self.summary())


def _row(case: Case, row: dict[str, Any], study: Study, version: str, run: int | None) -> dict[str, Any]:
    """The executor's row completed with what the case itself says (parameters, limits…)."""
    out = dict(row)
    out.update(key=case.key(version), params_key=case.params_key, study=study.name, kind=case.kind,
               series=case.series, params=case.params_json, version=version, time_limit=case.time_limit,
               memory_limit_mb=case.memory_limit_mb, run=run, seed=case.params.get("seed"))
    if out.get("size") is None:
        out["size"] = case.size
    if out.get("positioners") is None:
        out["positioners"] = case.positioners
    return out


class _Skips:
    """The ``skip_larger`` rule: failures seen so far, per block and series of parameters."""

    def __init__(self, study: Study, store: ResultStore, version: str, any_version: bool = False):
        self.failed: dict[tuple, tuple[Any, str]] = {}
        found = records(study, store, version, any_version)
        for case in study.cases:
            record = found.get(case.params_key)
            if record and record[0] in ("timeout", "out-of-memory") and is_done(record, case):
                self.note(case, record[0])

    @staticmethod
    def _group(case: Case) -> tuple:
        rest = {k: v for k, v in case.params.items() if k not in (case.skip_larger, "seed")}
        return case.block, repr(sorted(rest.items()))

    def note(self, case: Case, status: str) -> None:
        if case.skip_larger is None:
            return
        value = case.params.get(case.skip_larger)
        group = self._group(case)
        if group not in self.failed or value < self.failed[group][0]:
            self.failed[group] = (value, status)

    def waits_for(self, case: Case, running: list[Case]) -> bool:
        """Whether a smaller case of the same ``skip_larger`` series is still running (its
        outcome decides whether ``case`` runs at all)."""
        if case.skip_larger is None:
            return False
        group, value = self._group(case), case.params.get(case.skip_larger)
        return any(other.skip_larger == case.skip_larger and self._group(other) == group
                   and other.params.get(case.skip_larger) < value for other in running)

    def reason(self, case: Case) -> str | None:
        if case.skip_larger is None or self._group(case) not in self.failed:
            return None
        value, status = self.failed[self._group(case)]
        if case.params.get(case.skip_larger) > value:
            return f"not run: {case.skip_larger} = {value} already ran {'out of time' if status == 'timeout' else 'out of memory'}"
        return None


def run_study(study: Study, database: str | os.PathLike | None = None, *, workers: int | None = None,
              scheduler: str | None = None, progress: Callable[[str], None] | None = print,
              version: str | None = None, retry: Iterable[str] = (), any_version: bool = False,
              command: str = "") -> RunSummary:
    """Run the cases of ``study`` not yet done (small first, each in a process of its own),
    committing each case's row as it ends, so an interrupted run resumes where it stopped.

    Parameters
    ----------
    study : Study
        The cases, their time limits (s) and memory limits (MB) (:func:`~.spec.load_study`).
    database : str or path-like, optional
        The SQLite results database; None: the study's own (``study.database_path()``).
    workers : int, optional
        Processes of an embedded Dask cluster; 0: one case after another, here; None: the study's, else 2.
    scheduler : str, optional
        An existing Dask scheduler (``"tcp://host:8786"``), whose workers run the same code version.
    progress : callable, optional
        Receives one line per finished case (done/failed/total, throughput, time left); None: silent.
    version : str, optional
        The code version recorded with each row; None: :func:`~.machine.code_version`.
    retry : iterable of str
        Failed statuses whose cases run again (``timeout``, ``out-of-memory``, ``error``, ``crashed``, ``lost``).
    any_version : bool
        Count a case recorded by any code version as done (to resume a long study across
        commits that did not change what it measures; new rows get this version).
    command : str
        The command line recorded with the run.

    Returns
    -------
    RunSummary
        Cases pending, run and failed, per status; the wall time (s); whether interrupted.

    Raises
    ------
    InputError
        ``workers`` < 0, a ``retry`` status that is no failure, an unreachable ``scheduler`` or
        one of another version (``where``: the parameter); a database that is not a study's.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from supcoord.study import study_from_dict
    >>> study = study_from_dict({"name": "mini", "cases": [{"kind": "call", "function": "math:sqrt", "args": [4]}]})
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     summary = run_study(study, pathlib.Path(tmp) / "r.sqlite", workers=0, progress=None)
    >>> summary.ran, summary.statuses
    (1, {'ok': 1})

    References
    ----------
    .. [1] M. Rocklin, "Dask: parallel computation with blocked algorithms and task scheduling",
       SciPy 2015, doi:10.25080/Majora-7b98e3ed-013.
    """
    version = version or code_version()
    workers = workers if workers is not None else (study.workers if study.workers is not None else DEFAULT_WORKERS)
    if workers < 0:
        raise InputError(f"must be >= 0, got {workers}", value=workers, where="workers")
    path = study.database_path(database)
    with ResultStore(path, inputs=[study.path]) as store:
        unknown = sorted(set(retry) - set(FAILED))
        if unknown:
            raise InputError(f"can only retry failed statuses ({', '.join(FAILED)}), got {unknown[0]!r}",
                             value=unknown[0], where="retry")
        todo = pending(study, store, version, retry, any_version)
        summary = RunSummary(study.name, str(path), version, len(study.cases), len(todo), workers=workers)
        report = _report(study, store, todo, version, any_version, progress)
        if not todo:
            report.line(f"{study.name}: all {len(study.cases)} cases done ({path})")
            return summary
        summary.run = store.start_run(study=study.name, started=_now(), version=version, machine=machine(),
                                      cpu=cpu_model(), workers=workers, scheduler=scheduler or "", total=len(study.cases),
                                      pending=len(todo), command=command)
        report.line(f"{study.name}: {len(todo)} of {len(study.cases)} cases to run on "
                    f"{scheduler or (f'{workers} worker processes' if workers else 'this process, one after another')}"
                    f"; results in {path}")
        _execute(todo, _Recorder(study, store, version, any_version, summary, report), workers, scheduler)
        report.done(summary)
    return summary


def _report(study: Study, store: ResultStore, todo: list[Case], version: str, any_version: bool,
            progress: Callable[[str], None] | None) -> StudyProgress:
    """The progress lines of a run, counting the failures recorded before it."""
    found = records(study, store, version, any_version)
    due = {c.params_key for c in todo}
    already_failed = sum((found.get(c.params_key) or ("ok",))[0] in FAILED for c in study.cases
                         if c.params_key not in due)
    return StudyProgress(len(study.cases), len(study.cases) - len(todo), progress, already_failed)


class _Recorder:
    """Records each finished case of a run: its row in the store, the run's summary, the
    ``skip_larger`` failures and the progress line."""

    def __init__(self, study: Study, store: ResultStore, version: str, any_version: bool, summary: RunSummary,
                 report: StudyProgress) -> None:
        self.study, self.store, self.version, self.summary, self.report = study, store, version, summary, report
        self.skips = _Skips(study, store, version, any_version)

    def finish(self, case: Case, row: dict[str, Any]) -> None:
        summary = self.summary
        row = _row(case, row, self.study, self.version, summary.run)
        self.store.record(row)
        summary.ran += 1
        summary.statuses[row["status"]] = summary.statuses.get(row["status"], 0) + 1
        if row["status"] == "crashed" and summary.first_crash is None:
            summary.first_crash = f"{case.describe()}: {row.get('message') or 'no message'}"[:300]
        if row["status"] in ("timeout", "out-of-memory"):
            self.skips.note(case, row["status"])
        self.report.finished(case, row)


def _execute(todo: list[Case], recorder: _Recorder, workers: int, scheduler: str | None) -> None:
    """Run ``todo`` (serially, or on Dask) until done or interrupted, and close the run's record."""
    summary, version = recorder.summary, recorder.version
    t0 = time.perf_counter()
    try:
        with _sigterm_as_interrupt():
            if workers == 0 and scheduler is None:
                _serial(todo, recorder.skips, recorder.finish, version)
            else:
                _dask(todo, recorder.skips, recorder.finish, version, workers, scheduler)
    except KeyboardInterrupt:
        summary.interrupted = True
    summary.wall_seconds = time.perf_counter() - t0
    recorder.store.finish_run(summary.run, finished=_now(), ran=summary.ran, failed=summary.failed,
                              skipped=summary.statuses.get("skipped", 0), wall_seconds=summary.wall_seconds,
                              ended="interrupted" if summary.interrupted else "finished")


def _now() -> str:
    return datetime.now(UTC).isoformat(timespec="seconds")


def _task(case: Case, version: str) -> dict[str, Any]:
    return {"kind": case.kind, "params": case.params, "time_limit": case.time_limit,
            "memory_limit_mb": case.memory_limit_mb, "key": case.key(version), "pythonpath": list(case.pythonpath)}


def _skipped(reason: str) -> dict[str, Any]:
    return {"status": "skipped", "message": reason, "started": _now(), "machine": machine()}


def _serial(todo: list[Case], skips: _Skips, finish: Callable, version: str) -> None:
    for case in todo:
        reason = skips.reason(case)
        finish(case, _skipped(reason) if reason else execute({**_task(case, version), "worker": "local"}))


#: the stop names of the runs interrupted, set on each worker by :func:`_stop_on_worker`
_STOPPED: set[str] = set()


def _stop_on_worker(stop: str) -> None:
    """Run on every worker (``Client.run``) when a run is interrupted: its cases stop."""
    _STOPPED.add(stop)


def dask_case(task: dict[str, Any], stop: str | None = None) -> dict[str, Any]:
    """The Dask task of one case: :func:`~.isolate.execute` on the worker, polling about
    once a second whether the run named ``stop`` was interrupted (:func:`_stop_on_worker`;
    a flag of the worker process, so the task needs no client of its own, whose clean-up
    at the worker's end would print errors)."""
    try:
        from distributed import get_worker

        task = {**task, "worker": get_worker().address}
    except (ImportError, ValueError):  # not on a Dask worker
        pass
    return execute(task, (lambda: stop in _STOPPED) if stop else None)


def _dask(todo: list[Case], skips: _Skips, finish: Callable, version: str, workers: int,
          scheduler: str | None) -> None:
    try:
        from distributed import Client, LocalCluster, as_completed
        from distributed.scheduler import KilledWorker
    except ImportError as exc:  # pragma: no cover (a dependency)
        raise InputError(f"running on Dask needs dask[distributed] ({exc}); or use workers=0",
                         value=None, where="workers") from None
    cluster = client = stop = None
    try:
        if scheduler is None:
            import logging

            # memory_limit=0: Dask does not police memory, each case's own limit does; ":0": the
            # scheduler's HTTP endpoint on a free port (its default, 8787, may be taken); Dask's own
            # log is silenced (a case's outcome, failures included, is its row; connection
            # errors while the cluster closes are noise)
            with _workers_deaf_to_ctrl_c():
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, memory_limit=0,
                                       dashboard_address=":0", silence_logs=logging.CRITICAL)
        try:
            client = Client(cluster if cluster is not None else scheduler, timeout=30)
        except OSError as exc:
            raise InputError(f"cannot reach the Dask scheduler ({exc})", value=scheduler, where="scheduler") from None
        stop = f"supcoord-stop-{uuid.uuid4().hex}"
        if scheduler is not None:
            versions = set(client.run(code_version).values())
            if versions - {version}:
                raise InputError(f"the cluster's workers run supcoord {', '.join(sorted(versions))}, this process "
                                 f"{version}: install the same code on both", value=scheduler, where="scheduler")
            workers = max(1, len(client.scheduler_info().get("workers", {})))
        queue = collections.deque(todo)
        running: dict[str, Case] = {}
        done = as_completed()

        def hand_out() -> None:
            while queue and len(running) < 2 * workers:
                case = next((c for c in queue if not skips.waits_for(c, list(running.values()))), None)
                if case is None:  # every case left waits for a smaller one of its series
                    return
                queue.remove(case)
                reason = skips.reason(case)
                if reason:
                    finish(case, _skipped(reason))
                    continue
                future = client.submit(dask_case, _task(case, version), stop, pure=False,
                                       key=f"supcoord-case-{case.key(version)}-{uuid.uuid4().hex[:8]}")
                running[future.key] = case
                done.add(future)

        hand_out()
        for future in done:
            case = running.pop(future.key)
            try:
                row = future.result()
            except KilledWorker as exc:
                row = {"status": "lost", "message": f"the worker running it died, on every try ({exc})"[:500]}
            except Exception as exc:  # noqa: BLE001 (a failure of the executor, recorded with the case)
                row = {"status": "lost", "message": f"{type(exc).__name__}: {exc}"[:500]}
            if row.get("status") is not None:
                finish(case, row)
            hand_out()
    except KeyboardInterrupt:
        if client is not None and stop is not None:  # the running cases kill their processes within a second
            with contextlib.suppress(Exception):
                client.run(_stop_on_worker, stop)
                if scheduler is not None:  # (an embedded cluster's workers end with it anyway)
                    time.sleep(1.5)
        raise
    finally:  # closing the embedded cluster ends its workers, and with them their case processes
        for part in (client, cluster):
            if part is not None:
                with contextlib.suppress(Exception):
                    part.close(timeout=10)


@contextlib.contextmanager
def _workers_deaf_to_ctrl_c():
    """Start the embedded cluster with SIGINT ignored: its worker processes inherit the
    ignored signal (a disposition survives ``exec``, and Python then installs no
    ``KeyboardInterrupt`` handler; a blocked mask would not: multiprocessing resets it), so
    a Ctrl-C at the terminal, sent to the whole process group, stops this process alone,
    which stops the cases and closes the cluster, instead of printing a traceback from
    every worker.  A Ctrl-C during the seconds the cluster takes to start is lost."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


class _sigterm_as_interrupt:
    """Within the block, SIGTERM (Slurm's end of job, ``kill``) raises KeyboardInterrupt
    in the main thread, so a terminated run stops as cleanly as a Ctrl-C."""

    def __enter__(self):
        self.previous = None
        if threading.current_thread() is threading.main_thread():
            self.previous = signal.signal(signal.SIGTERM, self._raise)
        return self

    @staticmethod
    def _raise(signum, frame):
        raise KeyboardInterrupt

    def __exit__(self, *exc):
        if self.previous is not None:
            signal.signal(signal.SIGTERM, self.previous)
        return False
