"""Nothing lost, nothing unbounded: safe outputs, budgets that are checked, clean interrupts."""

import contextlib
import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from supcoord.bdd.budget import MAX_TIMEOUT, Budget, current_rss
from supcoord.cli.common import parse_size
from supcoord.cli.main import main
from supcoord.errors import BudgetExceeded, InputError
from supcoord.outputs import atomic_output, atomic_write_text, check_output

THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0],
    "target": [6, 6, 6],
}


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture
def problem_file(tmp_path):
    path = tmp_path / "p.json"
    path.write_text(json.dumps(THREE))
    return path


# --- outputs ----------------------------------------------------------------------------

def test_output_that_is_an_input_is_refused_before_any_work(problem_file, tmp_path):
    before = problem_file.read_bytes()
    os.symlink(problem_file.name, tmp_path / "link.json")
    for out in (problem_file, tmp_path / "." / "p.json", tmp_path / "sub" / ".." / "p.json"):
        (tmp_path / "sub").mkdir(exist_ok=True)
        code, stdout, err = run("solve", problem_file, "--out", out)
        assert code == 2 and stdout == "" and len(err.strip().splitlines()) == 1
        assert "also an input" in err
    code, _, err = run("solve", tmp_path / "link.json", "--out", problem_file)  # input through a link
    assert code == 2 and "also an input" in err
    code, _, err = run("check", problem_file, problem_file, "--figure", problem_file.with_suffix(".png"))
    assert code == 2  # (the plan file is the problem: refused as a plan, one line)
    assert problem_file.read_bytes() == before


def test_symlink_fifo_and_directory_outputs_are_refused(problem_file, tmp_path):
    target = tmp_path / "elsewhere.json"
    target.write_text("keep me")
    os.symlink(target, tmp_path / "out.json")
    code, _, err = run("solve", problem_file, "--out", tmp_path / "out.json")
    assert code == 2 and "symbolic link" in err and target.read_text() == "keep me"
    os.mkfifo(tmp_path / "fifo")
    code, _, err = run("solve", problem_file, "--out", tmp_path / "fifo")  # would block forever if opened
    assert code == 2 and "not a regular file" in err
    code, _, err = run("solve", problem_file, "--out", tmp_path)
    assert code == 2 and "is a directory" in err
    code, _, err = run("solve", problem_file, "--out", tmp_path / "plan.png", "--figure", tmp_path / "plan.png")
    assert code == 2 and "same file" in err


def test_read_only_directory_is_refused_before_the_work(problem_file, tmp_path, monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    real_access = os.access
    # as root every directory is writable, so the permission is simulated where it is asked
    monkeypatch.setattr("supcoord.outputs.os.access",
                        lambda path, mode: False if Path(path) == ro else real_access(path, mode))
    code, out, err = run("solve", problem_file, "--out", ro / "plan.json", "--json")
    assert code == 2 and out == "" and "not writable" in err and not list(ro.iterdir())


def test_check_output_library_errors_are_input_errors(tmp_path):
    with pytest.raises(InputError, match="must be a file name"):
        check_output(3)
    with pytest.raises(InputError, match="does not exist"):
        check_output(tmp_path / "missing" / "x.json")
    assert check_output(tmp_path / "new.json") == tmp_path / "new.json"


def test_atomic_write_keeps_the_old_file_when_the_writer_fails(tmp_path):
    path = tmp_path / "plan.json"
    path.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_output(path) as tmp:
            tmp.write_text("half")
            raise RuntimeError("disk full")
    assert path.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.json"]  # no temporary left
    atomic_write_text(path, "new")
    assert path.read_text() == "new"
    assert (path.stat().st_mode & 0o777) == 0o666 & ~_umask()


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full to simulate a full disk")
def test_full_disk_names_the_file_and_leaves_no_truncated_plan(problem_file, tmp_path, monkeypatch):
    out = tmp_path / "plan.json"
    out.write_text('{"old": true}')
    real_open = open

    def full_disk_open(file, mode="r", *args, **kwargs):
        if "w" in mode and Path(file).parent == tmp_path and Path(file).name.startswith(".plan.json"):
            return real_open("/dev/full", mode, *args, **kwargs)  # writes fail with ENOSPC
        return real_open(file, mode, *args, **kwargs)

    monkeypatch.setattr("builtins.open", full_disk_open)
    code, _, err = run("solve", problem_file, "--out", out)
    monkeypatch.undo()
    assert code == 2 and str(out) in err and len(err.strip().splitlines()) == 1
    assert json.loads(out.read_text()) == {"old": True}


def test_demo_refuses_a_file_as_its_directory_and_leaves_nothing_behind(tmp_path, monkeypatch):
    (tmp_path / "taken").write_text("x")
    code, _, err = run("demo", "--out", tmp_path / "taken")
    assert code == 2 and "not a directory" in err
    import supcoord.paper.demo as demo

    def boom(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(demo, "draw_demo", boom)
    code, _, err = run("demo", "--out", tmp_path / "new" / "demo")
    assert code == 130 and not (tmp_path / "new").exists()  # the directories it made are gone


# --- budgets ----------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs", [{"max_nodes": -1}, {"max_nodes": 1.5}, {"timeout": "5"}, {"timeout": 0},
                                    {"timeout": float("inf")}, {"timeout": float("nan")}, {"timeout": 1e10},
                                    {"max_memory": True}, {"max_memory": 0}])
def test_budget_refuses_bad_limits(kwargs):
    with pytest.raises(InputError):
        Budget(**kwargs)


def test_budget_memory_limit_raises_with_the_resident_size():
    budget = Budget(max_memory=2**20)
    assert current_rss() > 2**20
    with pytest.raises(BudgetExceeded, match="memory budget exceeded in tables") as exc:
        budget.check("tables")
    assert exc.value.stats["rss_bytes"] > 2**20 and exc.value.stats["stage"] == "tables"
    Budget(max_memory=2**50).check("tables")  # far away: nothing


@pytest.mark.parametrize("text, value", [("8G", 8 * 2**30), ("500M", 500 * 2**20), ("1.5GiB", int(1.5 * 2**30)),
                                         ("2097152", 2**21)])
def test_parse_size(text, value):
    assert parse_size(text) == value


@pytest.mark.parametrize("text", ["", "12X", "-5G", "nan", "inf", "1K"])
def test_parse_size_refuses(text):
    with pytest.raises(InputError, match="--max-memory"):
        parse_size(text)


@pytest.mark.parametrize("option, value", [("--timeout", "1e10"), ("--timeout", "inf"), ("--timeout", "nan"),
                                           ("--max-memory", "lots"), ("--max-nodes", "0")])
def test_budget_options_are_checked_before_the_work(problem_file, option, value):
    code, out, err = run("solve", problem_file, option, value)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and option in err
    assert str(MAX_TIMEOUT)[:4] in err or option != "--timeout" or value != "1e10"


def test_memory_budget_stops_a_command_with_exit_3(problem_file):
    code, out, err = run("solve", problem_file, "--max-memory", "1M", "--json")
    assert code == 3 and "memory budget exceeded" in err
    assert json.loads(out)["status"] == "unknown"


# --- interrupts -------------------------------------------------------------------------

@pytest.mark.timeout(120)
@pytest.mark.parametrize("delay", [0.15, 0.4, 1.0])
def test_sigint_at_any_time_is_one_line_and_exit_130(delay):
    """From the imports to the work: one line on stderr, exit 130, no traceback; a second
    interrupt 50 ms later changes nothing."""
    proc = subprocess.Popen([sys.executable, "-m", "supcoord.cli", "paper", "--positioners", "12", "--steps", "12",
                             "--model", "coupled"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(delay)
    proc.send_signal(signal.SIGINT)
    time.sleep(0.05)
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    lines = err.decode().strip().splitlines()
    assert proc.returncode == 130, err.decode()
    assert len(lines) == 1 and "interrupted" in lines[0] and "Traceback" not in err.decode()


@pytest.mark.timeout(60)
def test_an_interrupt_swallowed_by_the_work_still_ends_the_command():
    """A ``KeyboardInterrupt`` raised inside a ``__del__`` is only printed and the work goes
    on; the interrupt's deadline ends the process anyway: one line, exit 130."""
    code = ("import time\n"
            "from supcoord.cli.main import _interrupt_once\n"
            "_interrupt_once()\n"
            "end, told = time.time() + 40, False\n"
            "while True:\n"
            "    try:\n"
            "        if not told:\n"
            "            told = True\n"
            "            print('ready', flush=True)\n"
            "        while time.time() < end:\n"
            "            time.sleep(0.01)\n"
            "        break\n"
            "    except KeyboardInterrupt:\n"
            "        pass\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdout.readline().strip() == b"ready"
    started = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 130 and err.decode().strip().splitlines() == ["supcoord: interrupted"]
    assert time.monotonic() - started < 20


# --- the validator ----------------------------------------------------------------------

def _swing_through():
    """Bases (0, 0), (−20, 0), arm 15, 3 steps, buffer 1: positioner 0 turns from 1 to 2,
    its fibre passing 5 mm from the other's arm... through it."""
    from supcoord.problems.plan import Plan
    from supcoord.problems.problem import parse_problem

    problem = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [-20, 0]]},
                             "kinematics": {"kind": "rotary", "arm": 15, "steps": 3},
                             "collision": {"buffer": 1}, "start": [1, 0], "target": [2, 0]})
    return problem, Plan("complete", [[[1], [0]], [[2], [0]]], 1, 1, [], "", {})


@pytest.mark.parametrize("resolution", [1e-4, 0.05, 1.0, 10.0, 100.0])
def test_validator_verdict_does_not_depend_on_the_resolution(resolution):
    from supcoord.problems.validate import validate_plan

    problem, plan = _swing_through()
    result = validate_plan(problem, plan, resolution=resolution)
    assert not result.valid and result.collisions == 1


@pytest.mark.parametrize("resolution", [0, -1, 1e-9, 1e6, float("inf"), float("nan"), "5", True])
def test_validator_refuses_a_resolution_out_of_range(resolution):
    from supcoord.problems.validate import validate_plan

    problem, plan = _swing_through()
    with pytest.raises(InputError, match="resolution"):
        validate_plan(problem, plan, resolution=resolution)


def test_validator_reports_a_plan_for_another_problem():
    from supcoord.problems.plan import Plan
    from supcoord.problems.validate import validate_plan

    problem, _ = _swing_through()
    result = validate_plan(problem, Plan("complete", [[[1], [0], [0]], [[2], [0], [0]]], 1, 1, [], "", {}))
    assert not result.valid and "another problem" in result.problems[0]


def test_check_cli_resolution_and_timeout(tmp_path):
    problem, plan = _swing_through()
    pf, lf = tmp_path / "p.json", tmp_path / "plan.json"
    problem.dump(pf)
    plan.dump(lf, problem.kinematics)
    for res in ("100", "0.05"):
        code, out, _ = run("check", pf, lf, "--resolution", res, "--json")
        assert code == 0 and json.loads(out)["valid"] is False
    code, _, err = run("check", pf, lf, "--resolution", "inf")
    assert code == 2 and "--resolution" in err
    code, _, err = run("check", pf, lf, "--timeout", "1e10")
    assert code == 2 and "--timeout" in err


# --- determinism ------------------------------------------------------------------------

@pytest.mark.timeout(120)
def test_the_same_problem_gives_the_same_plan_on_a_slow_machine(monkeypatch):
    """Plan improvement is budgeted in re-plannings, not seconds: a clock that runs 1000x
    faster (a loaded machine) changes nothing."""
    import itertools

    import numpy as np

    import supcoord.planning.improve as improve
    from supcoord.planning.planner import solve
    from supcoord.problems.random import random_problem

    p = random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, {"kind": "rotary", "arm": 15, "steps": 12}, 2.0,
                       seed=0)
    normal = solve(p)
    ticks = itertools.count()
    monkeypatch.setattr(improve.time, "perf_counter", lambda: 1000.0 * next(ticks))
    slow = solve(p)
    assert normal.stats["improve_replans"] > 0 and normal.makespan < normal.stats["makespan_scheduled"]
    assert slow.makespan == normal.makespan and slow.events == normal.events
    assert all(np.array_equal(a, b) for a, b in zip(slow.configurations, normal.configurations))


@pytest.mark.parametrize("improve", [-1, 0.5, float("nan"), "5", True])
def test_solve_refuses_a_bad_improve_budget(improve):
    from supcoord.planning.planner import solve
    from supcoord.problems.problem import parse_problem

    with pytest.raises(InputError, match="improve"):
        solve(parse_problem(THREE), improve=improve)


def test_solve_refuses_what_is_not_a_problem():
    from supcoord.planning.planner import solve

    with pytest.raises(InputError, match="needs a Problem"):
        solve("problem.json")


# --- bounded inputs -----------------------------------------------------------------------

def test_problem_and_plan_readers_bound_what_a_file_may_ask(tmp_path):
    import sys as _sys

    limit = _sys.get_int_max_str_digits()
    _sys.set_int_max_str_digits(0)
    try:
        huge = dict(THREE, start=[int("9" * 5000), 0, 0])
        (tmp_path / "bigint.json").write_text(json.dumps(huge))
        plan = {"status": "complete", "configurations": [[int("9" * 5000), 0, 0]]}
        (tmp_path / "bigplan.json").write_text(json.dumps(plan))
    finally:
        _sys.set_int_max_str_digits(limit)
    (tmp_path / "p.json").write_text(json.dumps(THREE))
    code, _, err = run("solve", tmp_path / "bigint.json")
    assert code == 2 and "bigint.json" in err and "out of range" in err and len(err.strip().splitlines()) == 1
    code, _, err = run("check", tmp_path / "p.json", tmp_path / "bigplan.json")
    assert code == 2 and "bigplan.json" in err and len(err.strip().splitlines()) == 1
    for kin, field in (({"kind": "rotary", "arm": 15, "steps": 8000}, "kinematics.steps"),
                       ({"kind": "alpha-beta", "alpha": 7.4, "beta": 15, "alpha_steps": 10**4, "beta_steps": 10**4},
                        "alpha_steps")):
        (tmp_path / "k.json").write_text(json.dumps(dict(THREE, kinematics=kin)))
        started = time.perf_counter()
        code, _, err = run("solve", tmp_path / "k.json")
        assert code == 2 and "k.json" in err and field in err and time.perf_counter() - started < 5


def test_plan_reader_refuses_too_many_positions(tmp_path, monkeypatch):
    import supcoord.problems.plan as plan_module

    monkeypatch.setattr(plan_module, "MAX_PLAN_POSITIONS", 30)
    (tmp_path / "p.json").write_text(json.dumps(THREE))
    (tmp_path / "plan.json").write_text(json.dumps({"status": "complete", "configurations": [[0, 0, 0]] * 11}))
    code, _, err = run("check", tmp_path / "p.json", tmp_path / "plan.json")
    assert code == 2 and "30 positions" in err


def test_paper_refuses_runaway_sizes():
    for flag, value in (("--positioners", "10000000"), ("--steps", "100000")):
        argv = ["paper", "--positioners", "3", "--steps", "4", flag, value]
        code, _, err = run(*argv)
        assert code == 2 and flag in err and "at most" in err


def test_stack_limit_is_raised_for_deep_bdds():
    import resource

    from supcoord.bdd.backend import STACK_BYTES, load_backend

    load_backend("cudd")
    soft, hard = resource.getrlimit(resource.RLIMIT_STACK)
    assert soft == resource.RLIM_INFINITY or soft >= min(STACK_BYTES, hard)


def test_node_budget_is_checked_inside_images():
    """--max-nodes 1000 stopped a monolithic paper run at 24,057 live nodes (one check per
    iteration); now every image checks it, so the overrun is one image."""
    code, out, err = run("paper", "--positioners", "8", "--steps", "12", "--route", "monolithic",
                         "--max-nodes", "1000", "--json")
    assert code == 3
    stats = json.loads(out)["stats"]
    assert 1000 < stats["bdd_nodes"] < 5000 and stats["inside"] == "image"


@pytest.mark.parametrize("overlap, valid", [(0.0, True), (5e-10, True), (1e-6, False), (1e-3, False)])
def test_validator_takes_an_overlap_below_a_nanometre_for_the_rounding_of_a_touch(overlap, valid):
    """Arms that touch at exactly the buffer sum come out 1e-15 mm either side of it in
    double precision; the validator does not report an overlap under TIE (1e-9 mm), so it
    never rejects what the planner's own arithmetic found free, and reports anything deeper."""
    from supcoord.problems.plan import Plan
    from supcoord.problems.problem import parse_problem
    from supcoord.problems.validate import TIE, validate_plan

    assert TIE == 1e-9
    problem = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [34.0 - overlap, 0]]},
                             "kinematics": {"kind": "rotary", "arm": 15, "steps": 12},
                             "collision": {"buffer": 2}, "start": [0, 6], "target": [0, 6]}, check_collisions=False)
    result = validate_plan(problem, Plan("complete", [[[0], [6]]], 0, 0, [], "", {}))
    assert result.valid is valid and result.collisions == (0 if valid else 1)
