"""Hostile PROBLEM.json / PLAN.json values that used to end in a traceback (exit 1) or be
taken silently: each is now one line on stderr and exit 2."""

from __future__ import annotations

import contextlib
import dataclasses
import io
import json
from pathlib import Path

import pytest

import supcoord
from supcoord.cli.main import main
from supcoord.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"


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


# --- the library: mutated problems, malformed plans, huge sizes -------------------------------

import copy  # noqa: E402
import signal  # noqa: E402

import numpy as np  # noqa: E402

from supcoord.errors import SupcoordError  # noqa: E402


@pytest.fixture(scope="module")
def solved():
    problem = supcoord.load_problem(EXAMPLES / "three_rotary.json")
    return problem, supcoord.solve(problem)


@contextlib.contextmanager
def answers_within(seconds):
    def hang(signum, frame):  # noqa: ARG001
        raise TimeoutError(f"no answer within {seconds} s")

    old = signal.signal(signal.SIGALRM, hang)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


MUTATIONS = {
    "target float (solve looped forever)": ("target", lambda p: p.target.astype(float) + 0.5),
    "start out of range": ("start", lambda p: np.full_like(p.start, 99)),
    "buffers NaN": ("buffers", lambda p: np.full(p.n, np.nan)),
    "priority None": ("priority", lambda p: None),
    "start a list": ("start", lambda p: p.start.tolist()),
    "kinematics None": ("kinematics", lambda p: None),
}


@pytest.mark.parametrize("mutation", sorted(MUTATIONS))
def test_a_mutated_problem_is_refused_by_solve_validate_and_figures(solved, mutation, tmp_path):
    problem, plan = solved
    field, value = MUTATIONS[mutation]
    bad = dataclasses.replace(copy.deepcopy(problem), **{field: value(problem)})  # a Problem refuses assignment
    for call in (lambda: supcoord.solve(bad), lambda: supcoord.validate_plan(bad, plan),
                 lambda: supcoord.plan_from_moves(bad, []), lambda: supcoord.save_plan_strip(bad, plan, tmp_path / "s.png")):
        with answers_within(20), pytest.raises(InputError, match=f"problem.{field}"):
            call()


def test_problem_arrays_cannot_be_changed_in_place(solved):
    problem, _ = solved
    for name in ("start", "target", "bases", "buffers"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(problem, name)[0] = 1


@pytest.mark.parametrize("field, value", [
    ("configurations", [np.full((3, 1), 10**30, dtype=object)]), ("configurations", ["abc"]),
    ("configurations", None), ("configurations", [np.full((3, 1), 1.5)]), ("lattice", 7), ("status", 3),
    ("makespan", "x"), ("angles_deg", [np.full((3, 1), np.nan)]), ("configurations", [np.zeros((19, 1), int)]),
])
def test_validate_plan_never_raises_on_a_malformed_plan(solved, field, value):
    problem, plan = solved
    bad = copy.deepcopy(plan)
    object.__setattr__(bad, field, value)
    result = supcoord.validate_plan(problem, bad)
    assert result.valid is False and result.problems


def test_plan_of_another_problem_is_refused_by_the_figures(solved, tmp_path):
    problem, _ = solved
    other = supcoord.load_problem(EXAMPLES / "hex19_rotary.json")
    plan = supcoord.Plan("complete", [other.start, other.start])
    with pytest.raises(InputError, match="another problem"):
        supcoord.save_plan_strip(problem, plan, tmp_path / "s.png")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("call", [
    lambda: supcoord.random_instance(10**100, 8), lambda: supcoord.random_instance(3, 10**100),
    lambda: supcoord.paper_example(10**100), lambda: supcoord.Context(cache_size=""),
    lambda: supcoord.plan_from_moves(supcoord.load_problem(EXAMPLES / "three_rotary.json"), 5),
])
def test_huge_or_junk_sizes_are_input_errors(call):
    with answers_within(20), pytest.raises(SupcoordError):
        call()


def test_library_errors_name_parameters_and_the_command_line_names_options():
    from supcoord.paper.run import solve_paper

    with pytest.raises(InputError) as info:
        solve_paper(3, 8, "literal", route="bogus")
    assert info.value.where == "route" and "--" not in info.value.one_line()
    code, _, err = run("paper", "--positioners", "3", "--steps", "8", "--model", "coupled", "--route", "modular")
    assert code == 2 and "--route" in err and "use --route monolithic" in err
