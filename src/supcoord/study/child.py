"""The process one case runs in: ``python -m supcoord.study.child TASK.json RESULT.json``.

Started by :func:`supcoord.study.isolate.execute`, in a session of its own (so a time-out
kills it and anything it started, and a Ctrl-C at the terminal does not reach it), it:

1. asks the kernel to kill it if its parent dies (Linux ``PR_SET_PDEATHSIG``), so a case
   never outlives the worker that runs it, and exits at once if that parent is already
   gone;
2. puts the study's ``pythonpath`` folders first on ``sys.path`` (for ``call`` cases) and
   limits its address space to the case's memory limit (``RLIMIT_AS``: an allocation
   past it fails with :class:`MemoryError` or CUDD's out-of-memory error, recorded as
   ``out-of-memory``), before any heavy import;
3. runs the case (:func:`supcoord.study.cases.run_case`) and writes the measurement to
   ``RESULT.json`` (atomically: written beside it, then renamed), or, for an unexpected
   exception, ``{"status": "crashed", "message": ...}`` and exit status 1.
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


def _limit_memory(mb: float | None) -> None:
    if mb is None:
        return
    import resource

    limit = int(mb * 2**20)
    _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))


def _write(path: str, data: dict) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(data, f, default=str)
    os.replace(tmp, path)


def main(argv: list[str]) -> int:
    task_path, result_path = argv
    parent = os.environ.get("SUPCOORD_STUDY_PARENT")
    _die_with_parent(int(parent) if parent and parent.isdigit() else None)
    with open(task_path, encoding="utf-8") as f:
        task = json.load(f)
    _limit_memory(task.get("memory_limit_mb"))
    sys.set_int_max_str_digits(0)
    sys.path[:0] = task.get("pythonpath") or []
    try:
        from .cases import run_case

        result = run_case(task["kind"], task["params"], task.get("time_limit"), task.get("memory_limit_mb"))
    except BaseException as exc:  # noqa: BLE001 (a bug in the case, reported as 'crashed')
        lines = traceback.format_exception(exc)
        _write(result_path, {"status": "crashed", "message": f"{type(exc).__name__}: {' '.join(str(exc).split())}"[:500],
                             "extra": {"traceback": "".join(lines)[-2000:]}})
        return 1
    _write(result_path, result)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
