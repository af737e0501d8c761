"""``--max-memory`` and a study case's memory limit are hard limits (:mod:`supcoord.bdd.memory`,
:mod:`supcoord.cli.guard`): a run stops within 5 % of its budget, with exit 3 and
``"status": "unknown"``, even when the memory grows inside one long C operation."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from supcoord.bdd.backend import load_backend
from supcoord.bdd.memory import MemoryCap


def _worst_order_conjunction(bdd, n: int) -> None:
    """``⋀ x_i ⇔ y_i`` with every x above every y: 2^n nodes, grown inside CUDD."""
    xs, ys = [f"x{i}" for i in range(n)], [f"y{i}" for i in range(n)]
    bdd.configure(reordering=False)
    bdd.declare(*xs, *ys)
    f = bdd.true
    for x, y in zip(xs, ys):
        f = f & bdd.apply("<=>", bdd.var(x), bdd.var(y))


def _child_peak(argv: list[str]) -> tuple[int, str, str, int]:
    """Exit status, stdout, stderr and peak resident bytes of a command (and its children)."""
    import tempfile

    import psutil

    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(argv, stdout=out, stderr=err, text=True)
        peak = 0
        while proc.poll() is None:  # VmHWM of the command and its child: ru_maxrss would start at pytest's
            try:
                family = [psutil.Process(proc.pid), *psutil.Process(proc.pid).children(recursive=True)]
            except psutil.Error:
                continue
            for p in family:
                try:
                    with open(f"/proc/{p.pid}/status") as f:
                        peak = max(peak, next(int(ln.split()[1]) * 1024 for ln in f if ln.startswith("VmHWM")))
                except (OSError, StopIteration):
                    pass
            time.sleep(0.02)
        out.seek(0), err.seek(0)
        return proc.returncode, out.read(), err.read(), peak


# 2^23 nodes grown inside CUDD: about 10 s on an idle machine, over a minute on a loaded one
@pytest.mark.slow
@pytest.mark.timeout(300)
def test_the_cap_stops_a_bdd_growing_inside_cudd_at_its_budget():
    code = (
        "import resource\n"
        "from supcoord.bdd.backend import load_backend\n"
        "from supcoord.bdd.memory import MemoryCap\n"
        "from tests.bdd.test_memory_cap import _worst_order_conjunction\n"
        "bdd = load_backend('cudd').BDD(initial_cache_size=2**14)\n"
        "with MemoryCap(150 * 2**20):\n"
        "    try:\n"
        "        _worst_order_conjunction(bdd, 23)\n"
        "    except (MemoryError, RuntimeError, ValueError) as exc:\n"
        "        print('stopped', type(exc).__name__)\n"
        "print(next(l.split()[1] for l in open('/proc/self/status') if l.startswith('VmHWM')))\n")
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=240, cwd=root)
    lines = proc.stdout.split()
    assert proc.returncode == 0 and lines[0] == "stopped", proc.stderr
    assert int(lines[-1]) * 1024 <= 1.05 * 150 * 2**20  # without the cap: 2^23 nodes, about 400 MiB


def test_without_a_budget_nothing_is_limited():
    import resource

    before = resource.getrlimit(resource.RLIMIT_DATA)
    with MemoryCap(2**40) as cap:
        assert cap.active and resource.getrlimit(resource.RLIMIT_DATA)[0] > 2**39
    assert resource.getrlimit(resource.RLIMIT_DATA) == before
    assert load_backend("cudd") is not None


@pytest.mark.slow
@pytest.mark.timeout(180)
def test_a_command_over_its_memory_budget_exits_3_within_5_percent():
    """The issue's class: a monolithic supcon whose image computations grow by tens of MiB
    at once (sampling alone let such runs pass their budget by 24 %)."""
    argv = [sys.executable, "-m", "supcoord.cli", "paper", "--positioners", "100", "--steps", "12",
            "--route", "monolithic", "--max-memory", "150M", "--json"]
    code, out, err, peak = _child_peak(argv)
    assert code == 3, err
    assert json.loads(out)["status"] == "unknown" and "memory budget exceeded" in err
    assert "Traceback" not in err
    assert peak <= 1.05 * 150 * 2**20


@pytest.mark.timeout(60)
def test_a_bug_in_the_forked_work_still_prints_its_traceback():
    """Under a memory budget the work runs in a forked child (:mod:`supcoord.cli.guard`); a bug
    there is exit 1 with its traceback, as without a budget, not a silent exit 1."""
    code = ("import sys\n"
            "from supcoord.cli import cmd_paper\n"
            "def broken(args, console):\n"
            "    raise ValueError('a planted bug')\n"
            "cmd_paper.run = broken\n"
            "from supcoord.cli.main import main\n"
            "sys.exit(main(['paper', '--positioners', '2', '--steps', '4', '--max-memory', '2G']))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=50)
    assert proc.returncode == 1
    assert "Traceback" in proc.stderr and "ValueError: a planted bug" in proc.stderr


@pytest.mark.timeout(90)
def test_an_interrupt_sent_to_the_command_alone_stops_its_forked_work():
    """SIGINT to the command's own process (a process manager's, not the terminal's, which
    reaches the whole group) is passed on to the forked work: one line, exit 130, no child left."""
    import psutil

    proc = subprocess.Popen([sys.executable, "-m", "supcoord.cli", "paper", "--positioners", "12", "--steps", "12",
                             "--model", "coupled", "--route", "monolithic", "--max-memory", "4G"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline, children = time.time() + 60, []
    while time.time() < deadline and not children and proc.poll() is None:
        time.sleep(0.05)
        children = psutil.Process(proc.pid).children()
    assert children, "the command did not fork its work"
    time.sleep(0.5)
    os.kill(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130 and err.strip().splitlines() == ["supcoord: error: interrupted"], err
    assert not any(c.is_running() and c.status() != psutil.STATUS_ZOMBIE for c in children)
