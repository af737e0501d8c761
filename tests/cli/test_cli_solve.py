"""``supcoord solve``: JSON plans, exit codes 0 (complete/infeasible), 2 (user errors), 3 (budgets)."""

import contextlib
import copy
import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from supcoord.cli.main import main
from supcoord.problems import load_problem, random_problem

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
    code, out, _ = run("solve", pf, "--json", "-q", "--require-all")
    plan = json.loads(out)
    assert code == 0 and plan["status"] == "infeasible"
    assert "positioners" in plan["reason"] and plan["configurations"] == []
    code, out, _ = run("solve", pf, "--figure", str(tmp_path / "why.png"), "--require-all")
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
    assert "node budget exceeded" in err and len(err.strip().splitlines()) == 1
    code, out, _ = run("solve", pf, "--json", "--timeout", "1e-9")
    assert code == 3 and json.loads(out)["status"] == "unknown"


def test_subprocess_once(tmp_path):
    pf = _write(tmp_path, "problem.json", THREE)
    proc = subprocess.run([sys.executable, "-m", "supcoord.cli", "solve", pf, "--json", "-q"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["status"] == "complete"


EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "docs" / "examples").glob("*.json"))
#: the answer each example file promises (docs/examples/README.md)
ANSWERS = {"three_rotary": "complete", "hex19_rotary": "complete", "sdss_v_unfold": "complete",
           "sdss_v_exact": "complete", "infeasible_triangle": "partial", "sdss_v_apo": "complete"}
#: examples that take minutes (a full wok: about a minute of CPU, docs/examples/README.md): parsed
#: here, solved and checked once by tests/docs/test_examples_smoke.py (every robot at its target)
SLOW_EXAMPLES = {"sdss_v_apo"}


def test_every_example_is_listed():
    assert sorted(p.stem for p in EXAMPLES) == sorted(ANSWERS)
    readme = (EXAMPLES[0].parent / "README.md").read_text()
    assert all(f"`{name}.json`" in readme for name in ANSWERS)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_parse_and_solve(tmp_path, path):
    problem = load_problem(path)
    assert problem.warnings == [] and problem.extra["name"] == path.stem and problem.extra["description"]
    if path.stem in SLOW_EXAMPLES:
        return
    plan_path = tmp_path / "plan.json"
    code, out, err = run("solve", str(path), "--out", str(plan_path), "--json", "-q")
    plan = json.loads(out)
    assert code == 0 and plan["status"] == ANSWERS[path.stem], err
    if plan["status"] in ("complete", "partial"):
        assert plan["lower_bound"] <= plan["makespan"]
        code, out, _ = run("check", str(path), str(plan_path), "--json")
        result = json.loads(out)
        assert code == 0 and result["valid"] and result["at_target"] == plan.get("on_target", problem.n)
    else:
        assert "positioners" in plan["reason"] and plan["stats"]["certificate"]


def test_an_unknown_plan_exits_3(tmp_path, monkeypatch):
    # a planner that answers "unknown" as a plan (instead of raising) still exits 3 (formats.md)
    import supcoord.planning.planner as planning_planner
    from supcoord.problems import Plan

    monkeypatch.setattr(planning_planner, "solve", lambda problem, **kw: Plan("unknown", [], reason="out of time"))
    code, out, err = run("solve", _write(tmp_path, "p.json", THREE), "--json")
    assert code == 3 and json.loads(out)["status"] == "unknown"
    code, out, err = run("solve", _write(tmp_path, "p.json", THREE))
    assert code == 3 and out.startswith("UNKNOWN: out of time")
