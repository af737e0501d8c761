"""A finer lattice where the problem's has only a single-move certificate (``supcoord.problems.refine``).

Six-robot random tight problems (:func:`~supcoord.testing.oracle.tight_problems.tight_angle_problem`,
exact start and target angles) whose lattice has only a single-move certificate while its
robots alone can move several joints at once (too many joints for the simultaneous search of
the whole).  ``solve`` then plans on the lattice with steps two-thirds as long.  Checked
against the independent oracle, which derives the finer problem itself from
``docs/formats.md`` (numbers of positions, the exact end angles it reads off its own
lattices): the certificate's robots really have no single-move plan on the coarse lattice,
and the plan replays as certified free, single moves and schedule, on the oracle's tables of
the finer one; ``supcoord check`` validates it from its ``lattice`` field.
"""

from __future__ import annotations

import contextlib
import io
import json
import math

import numpy as np
import pytest

from supcoord import solve
from supcoord.cli.main import main
from supcoord.errors import InputError
from supcoord.problems.plan import parse_event, parse_plan
from supcoord.problems.problem import parse_problem
from supcoord.problems.refine import at_lattice, finer_steps
from supcoord.problems.validate import validate_plan
from supcoord.testing.oracle import oracle_check_moves, oracle_check_steps, oracle_ends_deg, oracle_solve
from supcoord.testing.oracle.tight_problems import tight_angle_problem

#: seeds of six robots (found by a scan) that the finer lattice solves, and ones where it does not
SOLVED = (107, 116, 140, 144, 145, 148)
UNSOLVED = (92, 142)


def _case(seed: int) -> dict:
    return tight_angle_problem(seed, n=6, max_product=10**9)


def _finer_data(data: dict) -> dict:
    """The oracle's own finer problem: steps two-thirds as long (a wrapping alpha: 1.5·A
    positions; between hard stops 1.5·(A−1) intervals), the ends at the angles the oracle
    reads off the coarse problem's lattices."""
    kin = dict(data["kinematics"])
    a, b = kin["alpha_steps"], kin["beta_steps"]
    kin["alpha_steps"] = math.ceil(1.5 * (a - 1)) + 1 if "alpha_range" in kin else math.ceil(1.5 * a)
    kin["beta_steps"] = math.ceil(1.5 * (b - 1)) + 1
    start, target = oracle_ends_deg(data)
    return dict(data, kinematics=kin, start={"alpha_beta_deg": start.tolist()},
                target={"alpha_beta_deg": target.tolist()})


@pytest.mark.timeout(120)
@pytest.mark.parametrize("seed", SOLVED)
@pytest.mark.slow
def test_a_single_move_certificate_gives_way_to_a_plan_on_the_finer_lattice(seed):
    data = _case(seed)
    p = parse_problem(data)
    coarse = solve(p, improve=0, finer=None, when_incomplete="infeasible")
    assert coarse.status == "infeasible" and coarse.stats["certificate_model"] == "single-move"
    assert "refined" not in coarse.stats
    assert oracle_solve(data, members=coarse.stats["certificate"]) is None  # a real single-move certificate

    plan = solve(p, improve=0)
    fine = _finer_data(data)
    assert plan.status == "complete" and plan.lattice == (fine["kinematics"]["alpha_steps"],
                                                          fine["kinematics"]["beta_steps"])
    assert plan.stats["refined"]["certificate"] == coarse.stats["certificate"]
    moves = [parse_event(p.kinematics, e) for e in plan.events]
    assert moves and oracle_check_moves(fine, moves) is None
    assert oracle_check_steps(fine, plan.configurations) is None
    start, target = oracle_ends_deg(data)  # the exact angles, not the finer lattice's nearest
    wrap = np.array([360.0, 0.0]) if "alpha_range" not in data["kinematics"] else np.zeros(2)
    for got, want in ((plan.angles_deg[0], start), (plan.angles_deg[-1], target)):
        diff = np.abs(got - want)
        diff[:, 0] = np.where(wrap[0] > 0, np.minimum(diff[:, 0], 360.0 - diff[:, 0]), diff[:, 0])
        assert diff.max() < 1e-6

    # what `supcoord check` reads: the plan's file, validated on the lattice it names
    back = parse_plan(json.loads(json.dumps(plan.to_json(p))), p)
    assert back.lattice == plan.lattice
    assert validate_plan(p, back).valid
    back.lattice = None  # the same indices read on the problem's own lattice are another motion
    assert not validate_plan(p, back).valid


@pytest.mark.timeout(120)
@pytest.mark.parametrize("seed", UNSOLVED)
@pytest.mark.slow
def test_where_the_finer_lattice_has_no_plan_either_the_coarse_certificate_stands(seed):
    p = parse_problem(_case(seed))
    plan = solve(p, improve=0, when_incomplete="infeasible")
    assert plan.status == "infeasible" and plan.lattice is None
    assert plan.stats["certificate_model"] == "single-move"
    refined = plan.stats["refined"]
    assert refined["status"] == "infeasible" and refined["lattice"] == list(finer_steps(p))
    assert "on the finer" in plan.reason


def test_finer_steps_and_the_problem_on_them():
    data = _case(107)
    p = parse_problem(data)
    fine = at_lattice(p, finer_steps(p))
    assert fine.kinematics.shape == finer_steps(p) and fine.n == p.n
    np.testing.assert_allclose(fine.angles_deg(fine.start), p.angles_deg(p.start), atol=1e-9)
    np.testing.assert_allclose(fine.angles_deg(fine.target), p.angles_deg(p.target), atol=1e-9)
    np.testing.assert_allclose(fine.buffers, p.buffers)
    # a uniform lattice given by indices keeps its angles on the finer one
    ab = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7}
    q = parse_problem({"layout": {"kind": "hex", "rings": 1, "pitch": 22.4}, "kinematics": ab,
                       "collision": {"buffer": 1.0}, "start": [[0, 0]] * 7, "target": [[6, 6]] * 7})
    assert finer_steps(q) == (18, 10)  # alpha wraps: 1.5 × 12 positions
    assert finer_steps(q, (18, 10)) == (27, 15)  # the lattice finer again, for the same joints
    r = at_lattice(q, (18, 10))
    np.testing.assert_allclose(r.angles_deg(r.target), q.angles_deg(q.target), atol=1e-9)
    rotary = parse_problem({"layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
                            "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 12}, "collision": {"buffer": 1.0},
                            "start": [0] * 7, "target": [0] * 7})
    assert finer_steps(rotary) is None
    for bad in ((18,), (18, 10.5), (True, 10), (5000, 5000)):
        with pytest.raises(InputError, match="lattice"):
            at_lattice(q, bad)


def _cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


@pytest.mark.timeout(120)
def test_the_command_line_plans_on_the_finer_lattice_and_check_validates_it(tmp_path):
    problem = tmp_path / "problem.json"
    problem.write_text(json.dumps(_case(140)))
    plan_file = tmp_path / "plan.json"
    code, out, _ = _cli("solve", str(problem), "--no-refine", "--require-all", "--improve", "0", "--out", str(plan_file))
    assert code == 0 and out.startswith("INFEASIBLE") and "lattice" not in json.loads(plan_file.read_text())
    code, out, _ = _cli("solve", str(problem), "--improve", "0", "--speed", "30", "--out", str(plan_file))
    written = json.loads(plan_file.read_text())
    assert code == 0 and "planned on the finer 9 × 6 lattice" in out and written["lattice"] == [9, 6]
    code, out, _ = _cli("check", str(problem), str(plan_file))
    assert code == 0 and out.startswith("VALID"), out
    written["lattice"] = [9, 7]  # the indices on another lattice: another motion, or outside it
    plan_file.write_text(json.dumps(written))
    code, out, _ = _cli("check", str(problem), str(plan_file))
    assert code == 0 and out.startswith("INVALID"), out
    written["lattice"] = [9, "6"]
    plan_file.write_text(json.dumps(written))
    code, _, err = _cli("check", str(problem), str(plan_file))
    assert code == 2 and "lattice must list 2 numbers of positions" in err and err.count("\n") == 1
