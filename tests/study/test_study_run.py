"""Running studies one case after another (``--workers 0``): every outcome recorded, resume
after an interruption, export, plots, progress, and the command line's one-line errors.

Each case runs in a process of its own (:mod:`supcoord.study.isolate`), so these tests
start real processes; the cases are small (or stdlib functions through the ``call``
kind: ``time:sleep`` past its limit, ``os:abort``, a huge ``bytearray``).
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from supcoord.cli.main import main
from supcoord.study import (
    export_results,
    load_study,
    results_frame,
    results_rows,
    run_study,
)

STUDY = """
name = "small"
time_limit = 20
memory_limit = "2 GiB"

[[cases]]
kind = "paper"
steps = 6
positioners = [2, 3]

[[cases]]
kind = "solve"
problem = "random"
kinematics = { kind = "rotary", arm = 15.0, steps = 12 }
rings = 1

[[cases]]
kind = "supcon"
family = "dining_philosophers"
size = 4

[[cases]]
kind = "call"
function = "time:sleep"
args = [60]
time_limit = 0.5

[[cases]]
kind = "call"
function = "os:abort"

[[cases]]
kind = "call"
function = "builtins:bytearray"
args = [4000000000]
"""


def cli(*argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    """The small study, run once through the command line; (study file, database, JSON, stderr)."""
    folder = tmp_path_factory.mktemp("study")
    path = folder / "small.toml"
    path.write_text(STUDY)
    code, out, err = cli("study", "run", path, "--workers", "0", "--json")
    assert code == 1, err  # os:abort crashed: a bug, not an answer
    return path, folder / "small.sqlite", json.loads(out), err


@pytest.mark.slow
def test_a_run_with_a_crashed_case_exits_1_with_one_line_naming_it(ran):
    *_, payload, err = ran
    last = err.strip().splitlines()[-1]
    assert last.startswith("supcoord: error: 1 of 7 cases crashed") and "os:abort" in last and "SIGABRT" in last
    assert payload["statuses"]["crashed"] == 1 and "os:abort" in payload["first_crash"]


@pytest.mark.timeout(120)
def test_every_outcome_is_recorded_with_what_it_reported(ran):
    _, db, payload, _ = ran
    assert payload["status"] == "finished" and payload["total"] == payload["ran"] == 7
    rows = {(r["series"], r["size"]): r for r in results_rows(db)}
    assert {r["status"] for r in rows.values()} == {"ok", "timeout", "crashed", "out-of-memory"}
    paper = rows[("paper literal modular", 3)]
    assert paper["verdict"] == "not forcible" and paper["bdd_nodes"] > 0 and paper["states"] == "209952"
    assert paper["peak_rss_mb"] > 20 and paper["cpu_seconds"] > 0 and paper["wall_seconds"] >= paper["seconds"]
    assert paper["version"] and paper["machine"] and paper["cpu"] and paper["started"] and paper["load"] is not None
    solve = rows[("solve rotary local", 7)]
    assert solve["verdict"] == "complete" and solve["makespan"] >= solve["lower_bound"] >= 1
    assert solve["extra"]["valid"] is True
    assert rows[("supcon dining_philosophers", 4)]["states"] == str(3**4 - 2)
    sleep, abort, alloc = (rows[(f"call {f}", None)] for f in ("time:sleep", "os:abort", "builtins:bytearray"))
    assert sleep["status"] == "timeout" and "time limit of 0.5 s" in sleep["message"]
    assert abort["status"] == "crashed" and "SIGABRT" in abort["message"]
    assert alloc["status"] == "out-of-memory" and "MemoryError" in alloc["message"]


def test_progress_lines_count_done_failed_total_with_throughput_and_time_left(ran):
    *_, err = ran
    lines = [ln for ln in err.splitlines() if ln.startswith("[")]
    assert len(lines) == 7
    assert lines[-1].startswith("[7/7] 4 ok, 3 failed, 0 left | ") and "cases/min" in lines[-1]
    assert "left |" in lines[0] and "about" in lines[0]
    assert "finished after" in err.splitlines()[-2]


@pytest.mark.slow
def test_a_second_run_has_nothing_left_and_show_says_so(ran):
    path, db, _, _ = ran
    code, out, err = cli("study", "run", path, "--workers", "0", "--json")
    assert code == 0 and json.loads(out)["ran"] == 0 and "all 7 cases done" in err  # nothing crashed in this run
    code, out, _ = cli("study", "show", path, "--json")
    shown = json.loads(out)
    assert code == 0 and (shown["total"], shown["done"], shown["left"]) == (7, 7, 0)
    assert {s["series"] for s in shown["series"]} >= {"paper literal modular", "call os:abort"}
    # a larger time limit makes the time-out due again, and only it
    study = load_study(path)
    assert len(run_study(study, db, workers=0, progress=None).statuses) == 0
    code, out, _ = cli("study", "show", path, "--time-limit", "30", "--json")
    assert json.loads(out)["left"] == 1
    # another code version has done nothing, unless any version counts
    code, out, _ = cli("study", "show", path, "--code-version", "other", "--json")
    assert json.loads(out)["left"] == 7
    code, out, _ = cli("study", "show", path, "--code-version", "other", "--any-version", "--json")
    assert json.loads(out)["left"] == 0


def test_export_csv_round_trip_and_dataframe(ran, tmp_path):
    _, db, _, _ = ran
    out = tmp_path / "r.csv"
    code, text, err = cli("study", "export", db, "--format", "csv", "--out", out, "--json")
    assert code == 0 and json.loads(text)["rows"] == 7, err
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    frame = results_frame(db)
    assert len(rows) == len(frame) == 7
    by_key = {r["key"]: r for r in rows}
    for _, r in frame.iterrows():
        back = by_key[r["key"]]
        assert back["status"] == r["status"] and back["series"] == r["series"]
        if r["seconds"] == r["seconds"]:  # not NaN
            assert float(back["seconds"]) == pytest.approx(r["seconds"])
    assert "steps" in frame.columns and "extra" in frame.columns  # parameters spread into columns


def test_export_parquet(ran, tmp_path):
    pytest.importorskip("pyarrow")
    import pandas as pd

    _, db, _, _ = ran
    assert export_results(db, tmp_path / "r.parquet") == 7
    assert len(pd.read_parquet(tmp_path / "r.parquet")) == 7


def test_plots_from_the_database(ran, tmp_path):
    _, db, _, _ = ran
    code, out, err = cli("study", "plot", db, "--out", tmp_path / "fig", "--json")
    assert code == 0, err
    figures = [Path(p) for p in json.loads(out)["figures"]]
    assert [p.stem for p in figures] == ["time", "memory", "nodes", "verdicts", "quality"]
    assert all(p.stat().st_size > 5000 for p in figures)


@pytest.mark.parametrize("text, field, value", [
    ('[[cases]]\nkind = "paper"\nsteps = 6\npositioners = "ten"\n', "cases[0].positioners", "'ten'"),
    ('[[cases]]\nkind = "paper"\nsteps = 6\npositioners = 3\nroute = "sideways"\n', "cases[0].route", "'sideways'"),
    ('time_limit = "soon"\n[[cases]]\nkind = "paper"\n', "time_limit", "'soon'"),
    ("[[cases]\n", "bad.toml", "not valid TOML"),
])
def test_a_bad_study_file_is_one_line_and_exit_2(tmp_path, text, field, value):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    code, out, err = cli("study", "run", path, "--workers", "0")
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 1, err
    assert lines[0].startswith(f"supcoord: error: {path}") and field in lines[0] and value in lines[0]


def test_other_command_line_mistakes_are_one_line(tmp_path):
    for argv, expected in ((["study", "run", tmp_path / "none.toml"], "study file not found"),
                           (["study", "show", tmp_path / "none.sqlite"], "no results database"),
                           (["study", "export", tmp_path / "none.sqlite"], "no results database")):
        code, _, err = cli(*argv)
        assert code == 2 and err.count("\n") == 1 and expected in err, err


SLOW = """
name = "slow"
time_limit = 30
[[cases]]
kind = "call"
function = "time:sleep"
args = [[0.3], [0.31], [0.32], [0.33], [0.34]]
"""


def _children(pid: int) -> list[int]:
    import psutil

    try:
        return [p.pid for p in psutil.Process(pid).children(recursive=True)]
    except psutil.NoSuchProcess:
        return []


@pytest.mark.timeout(90)
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL], ids=["ctrl-c", "kill-9"])
def test_an_interrupted_run_loses_nothing_and_the_next_resumes(tmp_path, sig):
    path = tmp_path / "slow.toml"
    path.write_text(SLOW)
    db = tmp_path / "slow.sqlite"
    proc = subprocess.Popen([sys.executable, "-m", "supcoord.cli", "study", "run", str(path), "--workers", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    done, children = 0, []
    # catch the run while a case is under way (on a loaded machine, polled between two cases,
    # the run may hold no child for a moment)
    while time.time() < deadline and not (done >= 1 and children):
        time.sleep(0.1)
        if db.exists():
            with contextlib.closing(sqlite3.connect(db)) as con, contextlib.suppress(sqlite3.OperationalError):
                done = con.execute("SELECT count(*) FROM cases").fetchone()[0]
        children = _children(proc.pid)
    assert done >= 1 and children, "the run did not get going"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=30)
    if sig == signal.SIGINT:
        assert proc.returncode == 130 and "interrupted" in err and "run again to resume" in err, err
    import psutil

    def running(pid: int) -> bool:
        try:
            return psutil.Process(pid).status() != psutil.STATUS_ZOMBIE
        except psutil.NoSuchProcess:
            return False

    deadline = time.time() + 10  # a killed process may take a moment to be torn down on a loaded machine
    while time.time() < deadline and any(running(c) for c in children):
        time.sleep(0.1)
    alive = [c for c in children if running(c)]
    assert not alive, [psutil.Process(c).cmdline() for c in alive]
    before = len(results_rows(db))
    assert 1 <= before < 5 and all(r["status"] == "ok" for r in results_rows(db))
    summary = run_study(load_study(path), workers=0, progress=None)
    assert summary.pending == summary.ran == 5 - before and not summary.interrupted
    assert len(results_rows(db)) == 5
    if sig == signal.SIGINT:
        runs = sqlite3.connect(db).execute("SELECT ended FROM runs ORDER BY run").fetchall()
        assert [r[0] for r in runs] == ["interrupted", "finished"]


def test_python_api_builds_and_runs_a_study(tmp_path):
    from supcoord.study import study_from_dict

    study = study_from_dict({"name": "api", "cases": [{"kind": "force", "family": "machine_line", "size": [2, 3]}]})
    lines: list[str] = []
    summary = run_study(study, tmp_path / "api.sqlite", workers=0, progress=lines.append)
    assert summary.statuses == {"ok": 2} and len(lines) == 4
    assert [r["verdict"] for r in results_rows(tmp_path / "api.sqlite")] == ["forcible", "forcible"]
    assert os.path.exists(tmp_path / "api.sqlite")


def test_call_cases_find_their_module_on_the_study_pythonpath_and_get_their_size(tmp_path):
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "mymeasure.py").write_text(
        "def measure(positioners, factor=1):\n"
        "    return {'bdd_nodes': positioners * factor, 'verdict': 'fine', 'rank': 7}\n")
    (tmp_path / "mine.toml").write_text(
        'pythonpath = ["lib"]\n[[cases]]\nkind = "call"\nfunction = "mymeasure:measure"\n'
        'kwargs = { factor = 3 }\npositioners = [2, 5]\nseries = "mine"\n')
    summary = run_study(load_study(tmp_path / "mine.toml"), workers=0, progress=None)
    rows = results_rows(tmp_path / "mine.sqlite")
    assert summary.statuses == {"ok": 2}
    assert [(r["series"], r["positioners"], r["bdd_nodes"], r["verdict"], r["extra"]) for r in rows] == [
        ("mine", 2, 6, "fine", {"rank": 7}), ("mine", 5, 15, "fine", {"rank": 7})]


@pytest.mark.parametrize("params", [
    {"model": "literal", "route": "modular"}, {"model": "literal", "route": "monolithic"},
    {"model": "literal", "route": "monolithic", "semantics": "standard"},
    {"model": "coupled"}, {"model": "coupled", "route": "settled"}, {"model": "coupled", "route": "monolithic"},
    {"model": "coupled", "route": "monolithic", "semantics": "standard"}], ids=repr)
def test_every_model_and_route_a_paper_case_can_declare_is_measured(params):
    """Each route is measured by what it builds: V's states where it was counted, else none."""
    from supcoord.study.case_run import run_case
    from supcoord.study.kinds import check_params

    full = check_params("paper", {"positioners": 3, "steps": 6, **params}, "cases[0]")
    out = run_case("paper", full, 30, 2000)
    assert out.status == "ok" and out.verdict in ("forcible", "not forcible") and out.bdd_nodes > 0
    assert out.extra["route"] == full["route"] and out.extra["peak_nodes"] > 0
    if full["route"] == "settled":
        assert out.states is None and out.extra["settled"]["relations"] > 0
    else:
        assert int(out.states) > 0


@pytest.mark.timeout(60)
def test_a_case_that_forks_leaves_nothing_running(tmp_path):
    """A child in the case's process group, and one that left it (setsid), both end with the case."""
    import psutil

    tag = f"{time.time():.6f}"[-7:]
    (tmp_path / "forks.toml").write_text(
        '[[cases]]\nkind = "call"\nfunction = "os:system"\n'
        f'args = [["sleep 6{tag} &"], ["setsid sleep 7{tag} &"]]\n')
    summary = run_study(load_study(tmp_path / "forks.toml"), workers=0, progress=None)
    assert summary.statuses == {"ok": 2}
    time.sleep(0.3)
    left = [p for p in psutil.process_iter(["cmdline"]) if tag in " ".join(p.info["cmdline"] or [])]
    assert not left, [p.info["cmdline"] for p in left]


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_ctrl_c_on_dask_workers_is_one_line_and_the_run_resumes(tmp_path):
    """Ctrl-C at a terminal reaches the whole process group: the workers must stay quiet."""
    path = tmp_path / "slow.toml"
    path.write_text(SLOW.replace("[[0.3], [0.31], [0.32], [0.33], [0.34]]",
                                 "[[1.0], [1.01], [1.02], [1.03], [1.04], [1.05], [1.06], [1.07]]"))
    proc = subprocess.Popen([sys.executable, "-m", "supcoord.cli", "study", "run", str(path), "--workers", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    db = tmp_path / "slow.sqlite"
    deadline, done = time.time() + 90, 0
    while time.time() < deadline and done < 1:
        time.sleep(0.2)
        if db.exists():
            with contextlib.closing(sqlite3.connect(db)) as con, contextlib.suppress(sqlite3.OperationalError):
                done = con.execute("SELECT count(*) FROM cases").fetchone()[0]
    assert done >= 1, "the run did not get going"
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    lines = err.strip().splitlines()
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "Exception ignored" not in err and "Warning" not in err, err
    assert lines[0].startswith("slow: 8 of 8 cases to run") and all(ln.startswith("[") for ln in lines[1:-1]), err
    assert "interrupted" in lines[-1] and "run again to resume" in lines[-1]
    summary = run_study(load_study(path), workers=0, progress=None)
    assert summary.ran == summary.pending == 8 - len(results_rows(db)) + summary.ran
    assert len(results_rows(db)) == 8


def test_a_case_dying_of_a_signal_at_its_memory_limit_is_out_of_memory_not_a_crash(tmp_path):
    """Some CUDD paths end the process (SIGSEGV) when an allocation fails under the limit."""
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "dies.py").write_text(
        "import os, signal\n"
        "def at(mb):\n"
        "    block = bytearray(mb * 2**20)\n"
        "    memoryview(block)[::4096] = b'x' * (len(block) // 4096)  # resident, page by page\n"
        "    os.kill(os.getpid(), signal.SIGSEGV)\n")
    (tmp_path / "dies.toml").write_text(
        'pythonpath = ["lib"]\nmemory_limit = "300 MB"\n[[cases]]\nkind = "call"\nfunction = "dies:at"\n'
        'args = [[220], [20]]\n')
    # through the command line: a case's ru_maxrss starts at its runner's peak (pytest's is large)
    subprocess.run([sys.executable, "-m", "supcoord.cli", "study", "run", str(tmp_path / "dies.toml"), "--workers", "0"],
                   capture_output=True, timeout=60)
    rows = {json.loads(r["params"])["args"][0]: r for r in results_rows(tmp_path / "dies.sqlite")}
    assert rows[220]["status"] == "out-of-memory" and "SIGSEGV" in rows[220]["message"], rows[220]
    assert rows[20]["status"] == "crashed"  # far below its limit: a bug


def test_a_small_case_run_by_a_large_runner_records_its_own_peak_memory(tmp_path):
    """The kernel starts a child's ru_maxrss at its parent's resident size: the case reports its own."""
    (tmp_path / "small.toml").write_text('[[cases]]\nkind = "call"\nfunction = "os:getpid"\n')
    ballast = bytearray(600 * 2**20)
    memoryview(ballast)[::4096] = b"x" * (len(ballast) // 4096)  # resident, page by page
    summary = run_study(load_study(tmp_path / "small.toml"), workers=0, progress=None)
    del ballast
    (row,) = results_rows(tmp_path / "small.sqlite")
    assert summary.statuses == {"ok": 1}
    assert 5 < row["peak_rss_mb"] < 400, row["peak_rss_mb"]
