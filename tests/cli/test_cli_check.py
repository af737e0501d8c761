"""``supcoord check``: JSON answers, exit 0 for (in)valid plans, exit 2 with one line for user errors.

The valid plans checked are the independent oracle's (``problem_cases.oracle_plan_moves``), not the planner's.
"""

import contextlib
import copy
import io
import json

import numpy as np
from hypothesis import given, settings
from problem_cases import ROTARY, THREE, mutated_problems, oracle_plan_moves

from supcoord.cli.main import main
from supcoord.problems import Plan, parse_problem, plan_from_moves


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def _write(tmp_path, name, data):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return str(path)


def test_valid_and_invalid_plans_exit_0(tmp_path):
    problem = parse_problem(copy.deepcopy(THREE))
    plan = plan_from_moves(problem, oracle_plan_moves(problem))
    pf = _write(tmp_path, "problem.json", THREE)
    good = _write(tmp_path, "plan.json", plan.to_json(problem.kinematics))
    code, out, _ = run("check", pf, good, "--json")
    result = json.loads(out)
    assert code == 0 and result["valid"] and result["collisions"] == 0 and result["at_target"] == 3
    assert set(result) >= {"valid", "collisions", "at_target", "problems"}
    jump = _write(tmp_path, "jump.json", Plan("complete", [problem.start, problem.target]).to_json(problem.kinematics))
    code, out, _ = run("check", pf, jump, "--json")
    result = json.loads(out)
    assert code == 0 and not result["valid"] and result["problems"]
    code, out, _ = run("check", pf, jump)
    assert code == 0 and out.startswith("INVALID")


def _one_line_error(code, out, err):
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("supcoord: error: ") and "Traceback" not in err
    return lines[0]


def test_user_errors_exit_2_with_one_line(tmp_path):
    pf = _write(tmp_path, "problem.json", THREE)
    plan = _write(tmp_path, "plan.json", {"status": "complete", "configurations": [[0, 0, 0]]})
    line = _one_line_error(*run("check", str(tmp_path / "nope.json"), plan, "--json"))
    assert "nope.json" in line and "not found" in line
    line = _one_line_error(*run("check", pf, _write(tmp_path, "broken.json", "{"), "--json"))
    assert "broken.json" in line and "not valid JSON" in line
    line = _one_line_error(*run("check", pf, _write(tmp_path, "short.json", {"status": "complete",
                                                                             "configurations": [[0, 0]]})))
    assert "configurations[0]" in line
    colliding = dict(THREE, start=[0, 6, 0])
    line = _one_line_error(*run("check", _write(tmp_path, "c.json", colliding), plan))
    assert "start configuration collides: positioners 0 and 1" in line
    _one_line_error(*run("check", pf, plan, "--resolution", "0"))


@settings(max_examples=60)
@given(mutated_problems())
def test_fuzz_cli_exits_0_or_2_without_traceback(tmp_path_factory, data):
    tmp = tmp_path_factory.mktemp("fuzz")
    pf = _write(tmp, "problem.json", json.dumps(data, allow_nan=True))
    start = data.get("start") if isinstance(data, dict) else None
    plan = _write(tmp, "plan.json", {"status": "complete", "configurations": [start] if isinstance(start, list) else []})
    code, out, err = run("check", pf, plan, "--json")
    assert code in (0, 2), err
    if code == 2:
        _one_line_error(code, out, err)
    else:
        assert set(json.loads(out)) >= {"valid", "collisions", "at_target", "problems"}


def test_rotary_fixture_is_well_formed():
    assert parse_problem(copy.deepcopy(ROTARY)).n == 7
    assert np.all(parse_problem(copy.deepcopy(ROTARY)).target == 6)


def test_figure_draws_the_collisions_found(tmp_path):
    from PIL import Image

    pf = _write(tmp_path, "problem.json", THREE)
    confs = [[0, -k % 12, 0] for k in range(7)]  # 1 turns back through 0's arm
    plan = _write(tmp_path, "bad.json", {"status": "complete", "configurations": confs})
    code, out, _ = run("check", pf, plan, "--figure", str(tmp_path / "bad.png"), "--json")
    result = json.loads(out)
    assert code == 0 and not result["valid"] and result["incidents"][0]["positioners"] == [0, 1]
    assert Image.open(tmp_path / "bad.png").format == "PNG"
    code, out, _ = run("check", pf, plan, "--figure", str(tmp_path / "bad.gif"))
    assert code == 0 and "figure written to" in out and Image.open(tmp_path / "bad.gif").n_frames == 6 * 4 + 1
    line = _one_line_error(*run("check", pf, plan, "--figure", str(tmp_path / "bad.bmp")))
    assert "--figure must end in" in line and "bad.bmp" in line
    line = _one_line_error(*run("check", pf, plan, "--figure", str(tmp_path / "no" / "x.png")))
    assert "does not exist" in line


def test_unknown_fields_are_warned_on_stderr(tmp_path):
    problem = parse_problem(copy.deepcopy(THREE))
    plan = plan_from_moves(problem, oracle_plan_moves(problem))
    plan = _write(tmp_path, "plan.json", plan.to_json(problem.kinematics))
    pf = _write(tmp_path, "typo.json", dict(THREE, prority=[3, 2, 1]))
    code, out, err = run("check", pf, plan, "--json")
    assert code == 0 and json.loads(out)["valid"]
    assert err.strip() == (f"supcoord: warning: {pf}: unknown field 'prority' ignored (known: layout, kinematics, collision, "
                           "start, target, priority, weight, offline, fixed, fibre, name, description, comment, preset, seed, "
                           "target_ids)")
