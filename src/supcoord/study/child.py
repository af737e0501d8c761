"""The process one case runs in: ``python -m supcoord.study.child TASK.json RESULT.json``.

Started by :func:`supcoord.study.isolate.execute`, in a session of its own (so a time-out
kills it and anything it started, and a Ctrl-C at the terminal does not reach it), it:

1. asks the kernel to kill it if its parent dies (Linux ``PR_SET_PDEATHSIG``), so a case
   never outlives the worker that runs it, and exits at once if that parent is already
   gone;
2. puts the study's ``pythonpath`` folders first on ``sys.path`` (for ``call`` cases) and
   limits its resident memory to the case's memory limit (:class:`~supcoord.bdd.memory.MemoryCap`,
   ``RLIMIT_DATA`` re-aimed as the case runs: an allocation past it fails with
   :class:`MemoryError` or CUDD's out-of-memory error, recorded as ``out-of-memory``),
   before any heavy import;
3. becomes the subreaper of the processes the case starts, and kills them when the case
   ends (a case that forks leaves nothing running);
4. runs the case (:func:`supcoord.study.case_run.run_case`) and writes its measurement
   (:meth:`~supcoord.study.case_run.Measurement.to_json`, with its own peak resident
   memory) to ``RESULT.json`` (atomically:
   written beside it, then renamed), or, for an unexpected exception,
   ``{"status": "crashed", "message": ...}`` and exit status 1.
"""

from __future__ import annotations

import json
import os
import signal
import sys
import traceback


def _die_with_parent(parent: int | None) -> None:
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux: the parent's time limit still kills the case
        pass
    if parent is not None and os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(137)


def _adopt_orphans() -> None:
    """Become the subreaper of the processes the case starts (Linux
    ``PR_SET_CHILD_SUBREAPER``): one whose parent exits is re-parented here rather than to
    init, so :func:`_end_descendants` finds it."""
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER
    except (OSError, AttributeError):
        pass


def _end_descendants() -> None:
    """Kill and reap every process the case started and left running (its children, and
    through :func:`_adopt_orphans` their orphans), so none outlives the case."""
    try:
        import psutil
    except ImportError:  # pragma: no cover (a dependency of dask.distributed)
        return
    for _ in range(3):  # an orphan is re-parented here only once its parent is gone
        try:
            left = psutil.Process().children(recursive=True)
        except psutil.Error:
            return
        if not left:
            return
        for p in left:
            try:
                p.kill()
            except psutil.Error:
                pass
        psutil.wait_procs(left, timeout=2)


def _limit_memory(mb: float | None):
    """The case's hard memory limit (:class:`~supcoord.bdd.memory.MemoryCap`), kept until
    the process ends (None: no limit)."""
    if mb is None:
        return None
    from ..bdd.memory import MemoryCap

    return MemoryCap(int(mb * 2**20)).__enter__()


def _write(path: str, data: dict) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(data, f, default=str)
    os.replace(tmp, path)


def main(argv: list[str]) -> int:
    parent = os.environ.get("SUPCOORD_STUDY_PARENT")
    _die_with_parent(int(parent) if parent and parent.isdigit() else None)
    _adopt_orphans()
    task_path, result_path = argv
    with open(task_path, encoding="utf-8") as f:
        task = json.load(f)
    cap = _limit_memory(task.get("memory_limit_mb"))
    try:
        return _run(task, result_path)
    finally:
        if cap is not None:
            cap.release()
        _end_descendants()


def _run(task: dict, result_path: str) -> int:
    sys.set_int_max_str_digits(0)
    sys.path[:0] = task.get("pythonpath") or []
    try:
        from .case_run import run_case

        result = run_case(task["kind"], task["params"], task.get("time_limit"), task.get("memory_limit_mb"))
    except BaseException as exc:  # noqa: BLE001 (a bug in the case, or the library not importable: 'crashed')
        lines = traceback.format_exception(exc)
        _write(result_path, {"status": "crashed", "message": f"{type(exc).__name__}: {' '.join(str(exc).split())}"[:500],
                             "extra": {"traceback": "".join(lines)[-2000:]}})
        return 1
    _write(result_path, {**result.to_json(), "peak_rss_mb": _own_peak_mb()})
    return 0


def _own_peak_mb() -> float | None:
    """This process's peak resident memory (MB) from ``VmHWM``, which ``exec`` starts afresh;
    the ``ru_maxrss`` its parent reads starts at the parent's resident size when it forked
    (Linux), so it overstates a small case run by a large worker.  None where unknown."""
    try:
        with open("/proc/self/status", "rb") as f:
            for line in f:
                if line.startswith(b"VmHWM:"):
                    return int(line.split()[1]) / 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
