"""Robot lattices unlocked around obstacles (``supcoord.problems.unlock``).

The case is the real one that motivated it: on SDSS-V's APO wok at 13 × 7, robot 386 at
(8.14°, 31.26°) (kaiju's instance seed 1) is boxed in by a fiducial on its own lattice; its
lattice gains one alpha angle and it folds.  Without the repair the same problem is
certified infeasible for the lattice, which the test checks too, so it cannot pass vacuously.
"""

from __future__ import annotations

import numpy as np
import pytest

import supcoord
from supcoord.problems import problem as problem_module
from supcoord.problems.problem import parse_problem
from supcoord.problems.unlock import alone_reachable, corner_angles, lattice_holding

pytestmark = pytest.mark.timeout(180)

BOXED = (8.141414275669685, 31.255559998239)


def _apo_one_robot_out(robot=386, angles=BOXED):
    start = [[10.0, 170.0]] * 500
    start[robot] = list(angles)
    return {"layout": {"kind": "instrument", "name": "sdss-v-apo"}, "start": {"alpha_beta_deg": start},
            "target": {"alpha_beta_deg": [[10.0, 170.0]] * 500}}


@pytest.mark.parametrize("wraps", [False, True])
def test_lattice_holding_keeps_every_needed_angle_and_the_size(wraps):
    table = np.linspace(0.0, 360.0, 13) if not wraps else 30.0 * np.arange(12)
    out = lattice_holding(table, [3.3, 200.0, 201.0], [8.1, 10.0], wraps)
    assert len(out) == len(table) and np.all(np.diff(out) > 0)
    assert {3.3, 200.0, 201.0, 8.1, 10.0} <= set(out.tolist())
    if not wraps:
        assert out[0] == 0.0 and out[-1] == 360.0  # hard stops stay
    assert lattice_holding(table, list(range(20)), [], wraps) is None  # more angles than positions


@pytest.mark.slow
def test_a_robot_boxed_in_by_a_fiducial_gets_a_way_out():
    p = parse_problem(_apo_one_robot_out())
    assert len(p.warnings) == 1 and p.warnings[0].startswith("robot 386:")
    kin = p.kin(386)
    assert np.allclose(kin.joint_angles_deg(p.start[386]), BOXED, atol=0)  # exact start kept
    assert alone_reachable(kin, p.unary()[386], p.start[386], p.target[386])
    again = parse_problem(p.to_json())  # the lattice is a function of the problem: check reads plans on it
    assert all(np.array_equal(again.kin(386).lattice_deg(j), kin.lattice_deg(j)) for j in (0, 1))
    assert np.array_equal(again.start, p.start) and np.array_equal(again.target, p.target)
    # that the repaired problem has a complete plan which passes the validator is shown by
    # test_solve_warns_and_check_reads_the_plan_on_the_same_lattices (one solve of the wok for both)


@pytest.mark.slow
def test_without_the_repair_the_lattice_has_no_plan(monkeypatch):
    monkeypatch.setattr(problem_module, "unlock_lattices", lambda problem: [])
    p = parse_problem(_apo_one_robot_out())
    assert not p.warnings
    assert not alone_reachable(p.kin(386), p.unary()[386], p.start[386], p.target[386])
    plan = supcoord.solve(p, improve=0, when_incomplete="infeasible")
    assert plan.status == "infeasible" and plan.stats["certificate"] == [386]


@pytest.mark.slow  # reads the 500-robot wok problem twice: seconds
def test_robots_that_are_free_keep_their_lattices(monkeypatch):
    data = _apo_one_robot_out(angles=(120.0, 60.0))
    p = parse_problem(data)
    assert not p.warnings
    monkeypatch.setattr(problem_module, "unlock_lattices", lambda problem: [])
    plain = parse_problem(data)
    assert all(np.array_equal(a.lattice_deg(j), b.lattice_deg(j))
               for a, b in zip(p.robot_kinematics, plain.robot_kinematics) for j in (0, 1))


@pytest.mark.slow
def test_solve_warns_and_check_reads_the_plan_on_the_same_lattices(tmp_path):
    import json
    import subprocess
    import sys

    problem, plan = tmp_path / "p.json", tmp_path / "plan.json"
    problem.write_text(json.dumps(_apo_one_robot_out()))
    solved = subprocess.run([sys.executable, "-m", "supcoord.cli", "solve", str(problem), "--out", str(plan),
                             "--improve", "0"], capture_output=True, text=True, timeout=150)
    assert solved.returncode == 0, solved.stderr
    assert "robot 386: its obstacles leave it no path on its lattice" in solved.stderr
    assert json.loads(plan.read_text())["status"] == "complete"  # the repaired robot folds too
    checked = subprocess.run([sys.executable, "-m", "supcoord.cli", "check", str(problem), str(plan), "--json"],
                             capture_output=True, text=True, timeout=150)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert json.loads(checked.stdout)["valid"] is True


@pytest.mark.parametrize("beta_range", [(0.0, 180.0), (0.0, 10.0), (90.0, 91.0)])
def test_the_fine_lattice_fits_the_table_limit_whatever_the_ranges(beta_range):
    from supcoord.geometry.alpha_beta import AlphaBeta
    from supcoord.geometry.joint_space import MAX_POSITIONS
    from supcoord.problems.unlock import _fine_kinematics

    lo, hi = beta_range
    kin = AlphaBeta(7.4, 15.0, 13, 7, beta_range, alpha_range=(0.0, 360.0))
    fine = _fine_kinematics(kin, [(8.1, lo + 0.3 * (hi - lo)), (10.0, hi)])
    assert fine.n_positions <= MAX_POSITIONS
    assert 8.1 in fine.lattice_deg(0).tolist() and hi in fine.lattice_deg(1).tolist()


def test_corner_angles_are_the_fixed_joint_of_each_segment():
    # α 8 -> 3 at β 31, β 31 -> 170 at α 3, α 3 -> 10 at β 170
    corners = [(8.0, 31.0), (3.0, 31.0), (3.0, 170.0), (10.0, 170.0)]
    assert corner_angles(corners) == [[3.0], [31.0, 170.0]]
