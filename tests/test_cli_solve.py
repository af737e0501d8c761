"""``supcoord solve``: JSON plans, exit codes 0 (complete/infeasible), 2 (user errors), 3 (budgets)."""

import contextlib
import copy
import io
import json
import subprocess
import sys

import numpy as np

from supcoord.cli.main import main
from supcoord.positioners import random_problem

THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0],
    "target": [6, 6, 6],
    "priority": [1, 2, 3],
}


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def _write(tmp_path, name, data):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return str(path)


def _infeasible():
    kin = {"kind": "rotary", "arm": 15.0, "steps": 12}
    p = random_problem(np.array([[0, 0], [18, 0], [9, 15]], float), kin, 2.0, seed=1)
    return p.to_json()


def test_solve_writes_a_plan_that_check_accepts(tmp_path):
    pf = _write(tmp_path, "problem.json", THREE)
    out_plan = str(tmp_path / "plan.json")
    fig = str(tmp_path / "plan.png")
    code, out, err = run("solve", pf, "--out", out_plan, "--figure", fig, "--json", "-q")
    assert code == 0, err
    plan = json.loads(out)
    assert plan["status"] == "complete" and plan["lower_bound"] == 6
    assert plan["makespan"] == len(plan["configurations"]) - 1 >= 6
    assert plan["configurations"][0] == THREE["start"] and plan["configurations"][-1] == THREE["target"]
    assert set(plan) >= {"status", "configurations", "makespan", "lower_bound", "events", "reason", "stats"}
    assert json.loads(open(out_plan).read()) == plan
    assert (tmp_path / "plan.png").stat().st_size > 0
    code, out, _ = run("check", pf, out_plan, "--json")
    assert code == 0 and json.loads(out)["valid"]
    code, out, _ = run("solve", pf, "--route", "monolithic")
    assert code == 0 and out.startswith("COMPLETE")


def test_infeasible_is_an_answer(tmp_path):
    pf = _write(tmp_path, "problem.json", _infeasible())
    code, out, _ = run("solve", pf, "--json", "-q")
    plan = json.loads(out)
    assert code == 0 and plan["status"] == "infeasible"
    assert "positioners" in plan["reason"] and plan["configurations"] == []
    code, out, _ = run("solve", pf, "--figure", str(tmp_path / "why.png"))
    assert code == 0 and out.startswith("INFEASIBLE") and "figure written to" in out
    assert (tmp_path / "why.png").stat().st_size > 1000


def test_user_errors_exit_2_with_one_line(tmp_path):
    code, out, err = run("solve", str(tmp_path / "missing.json"))
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    bad = copy.deepcopy(THREE)
    bad["start"] = [0, 6, 0]  # 0 points at 1 while 1 points back at 0
    code, _, err = run("solve", _write(tmp_path, "collide.json", bad), "--json")
    assert code == 2 and "positioners 0 and 1" in err and len(err.strip().splitlines()) == 1
    code, _, err = run("solve", _write(tmp_path, "garbage.json", "{not json"))
    assert code == 2 and len(err.strip().splitlines()) == 1
    pf = _write(tmp_path, "ok.json", THREE)
    code, _, err = run("solve", pf, "--timeout", "-1")
    assert code == 2 and len(err.strip().splitlines()) == 1
    code, _, err = run("solve", pf, "--figure", str(tmp_path / "x.txt"))
    assert code == 2 and len(err.strip().splitlines()) == 1
    # output paths are checked before any work is done
    for flag in ("--out", "--figure"):
        code, out, err = run("solve", pf, flag, str(tmp_path / "missing" / "plan.png"), "--json")
        assert code == 2 and out == "" and err.strip() == (
            f"supcoord: error: {flag}: directory '{tmp_path / 'missing'}' does not exist")
    code, _, err = run("solve", pf, "--out", str(tmp_path))
    assert code == 2 and "is a directory" in err


def test_budget_exits_3_with_unknown(tmp_path):
    # a problem that needs the exhaustive symbolic search (its answer is "infeasible")
    pf = _write(tmp_path, "problem.json", _infeasible())
    code, out, err = run("solve", pf, "--json", "--max-nodes", "1")
    payload = json.loads(out)
    assert code == 3 and payload["status"] == "unknown" and "stats" in payload
    assert payload["stats"]["positioners"] == 3
    assert err.strip().startswith("supcoord: error: node budget exceeded")
    code, out, _ = run("solve", pf, "--json", "--timeout", "1e-9")
    assert code == 3 and json.loads(out)["status"] == "unknown"


def test_subprocess_once(tmp_path):
    pf = _write(tmp_path, "problem.json", THREE)
    proc = subprocess.run([sys.executable, "-m", "supcoord.cli", "solve", pf, "--json", "-q"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["status"] == "complete"
