"""Hostile PROBLEM.json / PLAN.json values that used to end in a traceback (exit 1) or be
taken silently: each is now one line on stderr and exit 2."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

import supcoord
from supcoord.cli.main import main
from supcoord.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def refused(path, *extra):
    code, out, err = run("solve", path, "--timeout", "30", *extra)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, (code, err)
    return lines[0]


def unfold(**changes) -> dict:
    doc = json.loads((EXAMPLES / "sdss_v_unfold.json").read_text())
    doc.update(changes)
    return doc


@pytest.mark.parametrize("fibre", [["boss"], {"boss": 1}, 3])
def test_instrument_fibre_of_the_wrong_type_is_one_line(tmp_path, fibre):
    path = tmp_path / "p.json"
    path.write_text(json.dumps({"layout": {"kind": "instrument", "name": "sdss-v-apo", "fibre": fibre},
                                "start": "folded", "target": "folded"}))
    assert "layout.fibre" in refused(path)


def test_instrument_name_of_the_wrong_type_is_one_line(tmp_path):
    path = tmp_path / "p.json"
    path.write_text(json.dumps({"layout": {"kind": "instrument", "name": {"x": 1}}, "start": "folded",
                                "target": "folded"}))
    assert "layout.name" in refused(path)


@pytest.mark.parametrize("key", ["²", "٣", "３", "9" * 5001, "1.0", "", "-1", " 1"])
def test_offline_key_must_be_an_ascii_robot_index(tmp_path, key):
    path = tmp_path / "p.json"
    path.write_text(json.dumps(unfold(offline={key: [0, 180]})))
    assert "offline" in refused(path)


def test_offline_robot_given_twice_is_refused(tmp_path):
    path = tmp_path / "p.json"
    path.write_text(json.dumps(unfold(offline={"1": [0, 180], "01": [0, 180]})))
    assert "robot 1 is given twice" in refused(path)


def test_repeated_json_key_is_refused_in_problem_and_plan(tmp_path):
    text = json.dumps(unfold())
    path = tmp_path / "p.json"
    path.write_text(text[:-1] + ', "offline": {"1": [0, 180], "1": [0, 180]}}')
    line = refused(path)
    assert "'1' appears twice" in line and "p.json" in line
    path.write_text(text[:-1] + ', "start": "folded"}')
    assert "'start' appears twice" in refused(path)
    problem = EXAMPLES / "three_rotary.json"
    plan = tmp_path / "plan.json"
    plan.write_text('{"status": "complete", "status": "infeasible", "configurations": []}')
    code, _, err = run("check", problem, plan)
    assert code == 2 and "'status' appears twice" in err and len(err.strip().splitlines()) == 1


def test_offline_ascii_key_still_works():
    doc = unfold(offline={"0": [0, 180]})
    problem = supcoord.parse_problem(doc, None, False)
    assert list(problem.held) == [0]


@pytest.mark.parametrize("name", ["x" * 5000, "a\0b", "no/such/file.json"])
def test_load_problem_with_an_impossible_file_name_is_an_input_error(name):
    with pytest.raises(InputError) as info:
        supcoord.load_problem(name)
    assert len(str(info.value)) < 400
