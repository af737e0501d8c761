"""The command line of issue 37's operations: a colliding start repaired by ``solve``,
``--keep``, ``fixed``, and ``supcoord conflicts`` with its CSV."""

from __future__ import annotations

import contextlib
import csv
import io
import json

import pytest

from supcoord.cli.main import main

THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 6, 0],  # 0 points at 1, which points back: they collide
    "target": [6, 6, 6],
}


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def write(tmp_path, name, data):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return str(path)


def one_line(code, out, err):
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, (code, out, err)
    assert "Traceback" not in err
    return err.strip()


def test_solve_repairs_a_colliding_start_and_check_accepts_the_plan(tmp_path):
    pf, plan = write(tmp_path, "fault.json", THREE), tmp_path / "plan.json"
    code, out, err = run("solve", pf, "--out", plan)
    assert code == 0, err
    assert out.splitlines()[0].startswith("the start collides (1 pair, first robots 0 and 1): repaired first by moving "
                                          "robots ")
    data = json.loads(plan.read_text())
    assert data["status"] == "complete" and data["repair"]["minimum"] is True and len(data["repair"]["moved"]) == 1
    code, out, _ = run("check", pf, plan, "--json")
    assert code == 0 and json.loads(out)["valid"]
    del data["repair"]  # without its repair phase the same plan collides at once
    code, out, err = run("check", pf, write(tmp_path, "bare.json", data), "--json")
    assert "start configuration collides: positioners 0 and 1" in one_line(code, out, err)


def test_a_colliding_start_with_speed_is_repaired_then_timed_and_check_accepts_it(tmp_path):
    pf, plan = write(tmp_path, "fault.json", THREE), tmp_path / "plan.json"
    code, out, err = run("solve", pf, "--speed", "12", "--out", plan)
    assert code == 0, err
    first = out.splitlines()[0]
    assert first.startswith("the start collides (1 pair, first robots 0 and 1): repaired first by moving robots ")
    assert first.endswith(" s of the motion")
    data = json.loads(plan.read_text())
    assert data["repair"]["minimum"] is True and data["motion_time_s"] > 0 and len(data["trajectories"]) == 3
    code, out, err = run("check", pf, plan, "--json")
    assert code == 0 and json.loads(out)["valid"], out
    data["trajectories"][2]["theta"].insert(1, [0.001, data["trajectories"][2]["theta"][0][1] + 30.0])
    code, out, _ = run("check", pf, write(tmp_path, "moved.json", data), "--json")  # robot 2 moves in the repair
    verdict = json.loads(out)
    assert not verdict["valid"] and any(p.startswith("trajectories: repair") for p in verdict["problems"]), out


def test_a_colliding_start_with_jaeger_is_refused_before_the_work(tmp_path):
    line = one_line(*run("solve", write(tmp_path, "fault.json", THREE), "--jaeger", tmp_path / "j.json"))
    assert line.startswith("supcoord: error: --jaeger: the start collides (robots 0 and 1, 1 pair)")


def test_keep_holds_robots_at_their_start(tmp_path):
    data = dict(THREE, start=[0, 0, 0], target=[6, 6, 0])
    code, out, err = run("solve", write(tmp_path, "p.json", data), "--keep", "2", "--json")
    assert code == 0, err
    plan = json.loads(out)
    assert plan["status"] == "complete" and all(c[2] == 0 for c in plan["configurations"])


@pytest.mark.parametrize("keep, text", [("7", "--keep: '7' is not a robot index in [0, 2]"),
                                        ("1,x", "--keep: 'x' is not a robot index in [0, 2]"),
                                        ("-1", "--keep: '-1' is not a robot index in [0, 2]")])
def test_keep_out_of_range_is_one_line_naming_the_option(tmp_path, keep, text):
    line = one_line(*run("solve", write(tmp_path, "p.json", dict(THREE, start=[0, 0, 0])), f"--keep={keep}"))
    assert text in line


def test_bad_fixed_is_one_line_naming_file_field_and_value(tmp_path):
    pf = write(tmp_path, "p.json", dict(THREE, start=[0, 0, 0], fixed=[5]))
    line = one_line(*run("solve", pf))
    assert line == f"supcoord: error: {pf}: fixed[0]: 5 is not a robot index in [0, 2]"


FIELD = {"layout": {"kind": "points", "xy": [[0, 0], [12, 0], [24, 0], [36, 0], [100, 0], [120, 0]]},
         "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 12}, "collision": {"buffer": 1.5},
         "start": [3, 5, 3, 11, 3, 3], "target": [2, 10, 9, 10, 0, 6]}


def test_conflicts_writes_the_csv_an_assignment_program_reads(tmp_path):
    pf, out_csv = write(tmp_path, "field.json", FIELD), tmp_path / "pairs.csv"
    code, out, err = run("conflicts", pf, "--out", out_csv, "--json")
    assert code == 0, err
    payload = json.loads(out)
    rows = list(csv.DictReader(out_csv.open()))
    assert [(r["kind"], r["robots"]) for r in rows] == [("static-pair", "4 5"), ("planned-group", "0 1 2 3")]
    assert [c["kind"] for c in payload["conflicts"]] == [r["kind"] for r in rows]
    assert payload["searched"] == "complete" and payload["positioners"] == 6
    code, out, _ = run("conflicts", pf, "--max-groups", "0", "--json")
    assert [c["kind"] for c in json.loads(out)["conflicts"]] == ["static-pair"]


def test_conflicts_user_errors_are_one_line(tmp_path):
    pf = write(tmp_path, "field.json", FIELD)
    assert "--max-groups" in one_line(*run("conflicts", pf, "--max-groups", "-1"))
    assert "--out" in one_line(*run("conflicts", pf, "--out", pf))  # never over its input
    fault = write(tmp_path, "fault.json", THREE)
    assert "start configuration collides" in one_line(*run("conflicts", fault))
    code, out, _ = run("conflicts", fault, "--max-groups", "0", "--json")
    assert code == 0 and json.loads(out)["conflicts"] == []
