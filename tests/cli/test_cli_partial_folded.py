"""``supcoord solve --off-target-end folded`` (issue 37): the robots off target end folded where a
plan reaches it; PLAN.json says so, ``check`` accepts the plan and jaeger's trajectory of it."""

import contextlib
import io
import json
from pathlib import Path

import supcoord.planning.partial as partial_module
from supcoord.cli.main import main

#: three alpha-beta robots in a line, no plan puts all three on target; robot 2 can end folded
LINE = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [7.552936, 0.0], [15.105873, 0.0]]},
        "kinematics": {"kind": "alpha-beta", "alpha": 7.274, "beta": 15.357, "alpha_steps": 12,
                       "beta_steps": 3, "beta_range": [150.0, 180.0]},
        "collision": {"buffer": 2.013}, "start": [[3, 0], [2, 1], [2, 1]], "target": [[4, 1], [4, 2], [10, 2]]}


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def test_folded_ends_are_written_checked_and_exported_to_jaeger(tmp_path, monkeypatch):
    """Without parking (step 6 of the partial search), which would park robot 2 instead."""
    monkeypatch.setattr(partial_module, "park", lambda *args: None)
    problem = tmp_path / "problem.json"
    problem.write_text(json.dumps(LINE))
    plan, paths = tmp_path / "plan.json", tmp_path / "paths.json"
    code, out, err = run("solve", problem, "--off-target-end", "folded", "--improve", "0", "--out", plan,
                         "--jaeger", paths, "--rpm", "2")
    assert code == 0, err
    assert "ends folded" in out.splitlines()[0] and " folded)" in out
    data = json.loads(plan.read_text())
    folded = [e["robot"] for e in data["off_target"] if e["end"] == "folded"]
    assert data["status"] == "partial" and folded
    assert all(data["configurations"][-1][r][1] == 2 for r in folded)  # beta at its last position, 180°
    code, out, _ = run("check", problem, plan, "--json")
    assert code == 0 and json.loads(out)["valid"], out
    code, out, _ = run("check", problem, plan, "--jaeger", paths, "--max-rpm", "2", "--json")
    assert code == 0 and json.loads(out)["valid"], out
    beta = json.loads(paths.read_text())[str(folded[0])]["beta"]
    assert beta[-1][0] == 180.0


def test_an_unknown_off_target_end_is_one_line(tmp_path):
    problem = tmp_path / "problem.json"
    problem.write_text(json.dumps(LINE))
    code, out, err = run("solve", problem, "--off-target-end", "parked")
    assert code == 2 and out == "" and "--off-target-end" in err and "Traceback" not in err
