"""``supcoord solve`` with partial plans (issue 37): the answer in words and JSON, exit 0,
``--require-all``, and ``supcoord check`` accepting the plan."""

import contextlib
import io
import json
from pathlib import Path

from supcoord.cli.main import main

TRIANGLE = str(Path(__file__).resolve().parents[2] / "docs" / "examples" / "infeasible_triangle.json")


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def test_solve_answers_a_partial_plan_that_check_accepts(tmp_path):
    plan_path = str(tmp_path / "plan.json")
    code, out, err = run("solve", TRIANGLE, "--out", plan_path, "-v")
    assert code == 0, err
    assert out.splitlines()[0] == ("PARTIAL: 2 of 3 robots reach their targets; off target: robot 0 (group [0, 1, 2] "
                                   "has no plan with these robots on target)")
    assert out.splitlines()[1].startswith("optimal: ")
    assert "partial" in err  # the progress line while robots are left out
    plan = json.loads(Path(plan_path).read_text())
    assert plan["status"] == "partial" and plan["on_target"] == 2 and plan["optimal"] is True
    assert plan["off_target"][0]["robot"] == 0 and plan["off_target"][0]["end"] == "start"
    assert plan["off_target"][0]["certificate"]["members"] == [0, 1, 2]
    code, out, _ = run("check", TRIANGLE, plan_path, "--json")
    result = json.loads(out)
    assert code == 0 and result["valid"] and result["at_target"] == 2


def test_json_is_the_plan_file_and_require_all_keeps_the_verdict(tmp_path):
    code, out, _ = run("solve", TRIANGLE, "--json", "-q")
    assert code == 0 and json.loads(out)["status"] == "partial"
    code, out, _ = run("solve", TRIANGLE, "--json", "-q", "--require-all")
    plan = json.loads(out)
    assert code == 0 and plan["status"] == "infeasible" and "off_target" not in plan


def test_check_refuses_a_partial_plan_that_moves_a_listed_robot(tmp_path):
    plan_path = tmp_path / "plan.json"
    assert run("solve", TRIANGLE, "--out", str(plan_path), "-q")[0] == 0
    plan = json.loads(plan_path.read_text())
    plan["off_target"][0]["robot"] = 1  # robot 1 reaches its target: not where the entry says
    plan_path.write_text(json.dumps(plan))
    code, out, _ = run("check", TRIANGLE, str(plan_path), "--json")
    assert code == 0 and not json.loads(out)["valid"]


#: three alpha-beta robots in a line; robots 1 and 2 cannot both reach their targets and, on
#: this lattice, neither can with the other at its start: the plan parks robot 1 elsewhere
#: (step 6 of the partial search), which frees robot 2's target
ALPHA_BETA_PARTIAL = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [7.552936, 0.0], [15.105873, 0.0]]},
                      "kinematics": {"kind": "alpha-beta", "alpha": 7.274, "beta": 15.357, "alpha_steps": 12,
                                     "beta_steps": 3, "beta_range": [150.0, 180.0]},
                      "collision": {"buffer": 2.013}, "start": [[3, 0], [9, 2], [9, 2]],
                      "target": [[4, 1], [4, 2], [10, 2]]}


def test_a_partial_plan_is_exported_to_jaeger_and_checked_against_its_ends(tmp_path):
    problem = tmp_path / "problem.json"
    problem.write_text(json.dumps(ALPHA_BETA_PARTIAL))
    plan, there, back = (str(tmp_path / f) for f in ("plan.json", "paths.json", "back.json"))
    code, out, err = run("solve", str(problem), "--out", plan, "--jaeger", there, "--jaeger-reverse", back,
                         "--rpm", "2")
    assert code == 0, err
    assert "1 robots off target stay at their starts or park (1 parked) (positioner IDs 1; PLAN.json off_target)" in out
    assert "parked off target: robot 1 at lattice position (" in out and "freeing the target of robot 2" in out
    data = json.loads(Path(plan).read_text())
    assert [(e["robot"], e["end"]) for e in data["off_target"]] == [(1, "parked")]
    paths = json.loads(Path(there).read_text())
    assert paths["1"]["alpha"][-1][0] == data["angles_deg"][-1][1][0] != 270.0  # parked, not at its start
    assert paths["0"]["alpha"][-1][0] == 120.0  # its target
    for f, extra in ((there, []), (back, ["--reverse"])):
        code, out, _ = run("check", str(problem), plan, "--jaeger", f, "--json", *extra)
        assert code == 0 and json.loads(out)["valid"], out
    code, out, _ = run("check", str(problem), "--jaeger", there, "--json")  # without the plan: the targets
    result = json.loads(out)
    assert code == 0 and not result["valid"] and "does not end at the target" in result["problems"][0]
