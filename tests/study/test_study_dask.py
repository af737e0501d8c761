"""A study on a real Dask ``LocalCluster`` of 2 worker processes, one of which is killed
in the middle of a case: every finished case is in the database, the killed case is
recorded (re-run by Dask on a live worker, or recorded as lost), and a second run
does only what is left."""

from __future__ import annotations

import threading
import time

import pytest

from supcoord.study import results_rows, run_study, study_from_dict

psutil = pytest.importorskip("psutil")
pytest.importorskip("distributed")

CASES = [{"kind": "paper", "steps": 6, "positioners": [2, 3]},
         {"kind": "call", "function": "time:sleep", "args": [[1.0], [1.01], [1.02], [1.03], [1.04], [1.05]]}]


def _case_processes() -> list[psutil.Process]:
    """Running case processes (``supcoord.study.child``) started by a Dask worker of this test."""
    out = []
    for p in psutil.Process().children(recursive=True):
        try:
            parent = p.parent()
            if "supcoord.study.child" in p.cmdline() and parent is not None and "spawn_main" in " ".join(parent.cmdline()):
                out.append(p)
        except psutil.Error:
            pass
    return out


@pytest.mark.timeout(90)
@pytest.mark.slow
def test_a_killed_worker_loses_no_finished_case_and_the_next_run_does_only_what_is_left(tmp_path):
    study = study_from_dict({"name": "dask", "time_limit": 30, "cases": CASES})
    db = tmp_path / "dask.sqlite"
    lines: list[str] = []
    result: dict = {}
    runner = threading.Thread(target=lambda: result.setdefault("s", run_study(study, db, workers=2,
                                                                                progress=lines.append)))
    runner.start()
    victim = None
    deadline = time.time() + 60
    while time.time() < deadline and victim is None:
        time.sleep(0.1)
        finished = sum(ln.startswith("[") for ln in lines)
        running = _case_processes()
        if finished >= 2 and running:
            victim = running[0]
    assert victim is not None, f"no case was seen running on a worker: {lines}"
    worker = victim.parent()
    killed_at = sum(ln.startswith("[") for ln in lines)
    worker.kill()  # SIGKILL: the worker dies in the middle of its case; its case process dies with it
    victim.wait(timeout=10)
    runner.join(timeout=75)
    assert not runner.is_alive()
    summary = result["s"]
    rows = results_rows(db)
    assert len(rows) >= killed_at  # every case finished before the kill is there
    statuses = {r["status"] for r in rows}
    assert statuses <= {"ok", "lost"}, statuses  # the killed case: re-run (ok) or recorded as lost
    crashed = [r for r in rows if r["status"] == "lost"]
    assert all("worker" in r["message"] for r in crashed)
    assert len(rows) == summary.ran == len(study.cases) and summary.workers == 2
    assert {r["worker"] for r in rows if r["status"] == "ok"} - {None}  # ran on Dask workers
    # the second run: nothing is left but what the first one did not finish
    again = run_study(study, db, workers=2, progress=None)
    assert again.pending == len(crashed) and again.ran == len(crashed)
    assert all(r["status"] == "ok" for r in results_rows(db))
