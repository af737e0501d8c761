"""Starts and targets given as joint angles or fibre positions: held exactly, no snapping.

Checks the lattice rule (:func:`supcoord.geometry.kinematics.exact_lattice`) by its
defining properties on random cases, inverse kinematics against forward kinematics written
here, the PROBLEM.json forms and their errors, alpha hard stops and the clearance margin.
The planner's verdicts on such problems are compared with the independent oracle in
``tests/planning/test_exact_oracle.py``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from supcoord.errors import FormatError, InputError
from supcoord.geometry.kinematics import AlphaBeta, exact_lattice
from supcoord.problems.problem import parse_problem

pytestmark = pytest.mark.timeout(60)

KIN = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}
BASES = [[0.0, 0.0], [22.4, 0.0], [11.2, 19.4]]


def _problem(start, target, kin=None, collision=None, **extra):
    data = {"layout": {"kind": "points", "xy": BASES}, "kinematics": dict(kin or KIN),
            "collision": collision or {"buffer": 2.0}, "start": start, "target": target, **extra}
    return parse_problem(data, "p.json")


def _fibre(a_deg, b_deg, alpha=7.4, beta=15.0):
    a, b = math.radians(a_deg), math.radians(b_deg)
    return np.array([alpha * math.cos(a) + beta * math.cos(a + b), alpha * math.sin(a) + beta * math.sin(a + b)])


FOLDED = [[10.0, 170.0]] * 3
SPREAD = [[200.0, 100.0], [300.0, 40.0], [95.0, 60.0]]


@pytest.mark.parametrize("seed", range(3))
def test_lattice_holds_values_exactly_and_keeps_steps_short(seed):
    rng = np.random.default_rng(seed)
    for _ in range(3000):
        wraps = bool(rng.integers(2))
        n = int(rng.integers(3, 40))
        if wraps:
            grid = 360.0 * np.arange(n) / n
            values = rng.uniform(0, 360, 2)
        else:
            lo, hi = sorted(rng.uniform(-180, 180, 2))
            grid = lo + (hi - lo) * np.arange(n) / (n - 1)
            values = rng.uniform(lo, hi, 2)
        if rng.random() < 0.2:
            values[1] = values[0]
        if rng.random() < 0.3:
            values[int(rng.integers(2))] = grid[rng.integers(n)]  # an index-given value keeps its slot
        table, slots = exact_lattice(grid, values, wraps)
        h = grid[1] - grid[0]
        steps = np.diff(table)
        if wraps:
            steps = np.append(steps, table[0] + 360.0 - table[-1])
        assert steps.min() > 0 and steps.max() <= 2 * h * (1 + 1e-12)
        for v, s in zip(values, slots):
            assert table[s] == v or (wraps and (table[s] - v) % 360.0 == 0.0)
            if v in grid:
                assert s == int(np.nonzero(grid == v)[0][0])
        untouched = np.setdiff1d(np.arange(n), slots)
        assert np.array_equal(table[untouched], grid[untouched])


def test_inverse_kinematics_matches_forward_both_elbows():
    kin = AlphaBeta(7.4, 15.0, 12, 7, (-180.0, 180.0))
    rng = np.random.default_rng(5)
    for a, b in rng.uniform([0, -179], [360, 179], (500, 2)):
        sols = kin.inverse_deg(_fibre(a, b))
        assert len(sols) == 2
        for sa, sb in sols:
            assert np.abs(_fibre(sa, sb) - _fibre(a, b)).max() < 1e-9
        assert any(abs((sa - a + 180) % 360 - 180) < 1e-7 and abs(sb - b) < 1e-7 for sa, sb in sols)
        assert sols[0][1] >= 0 >= sols[1][1] or abs(sols[0][1]) == 180
    assert kin.inverse_deg([30.0, 0.0]) == [] and kin.inverse_deg([1.0, 0.0]) == []


def test_angles_are_held_exactly_and_round_trip():
    p = _problem({"alpha_beta_deg": FOLDED}, {"alpha_beta_deg": SPREAD})
    assert p.robot_kinematics is not None and len(p.robot_kinematics) == 3
    assert np.array_equal(p.angles_deg(p.start), np.array(FOLDED))
    assert np.array_equal(p.angles_deg(p.target), np.array(SPREAD))
    q = parse_problem(json.loads(json.dumps(p.to_json())))
    assert np.array_equal(q.start, p.start) and np.array_equal(q.target, p.target)
    assert [k.key() for k in q.robot_kinematics] == [k.key() for k in p.robot_kinematics]


def test_fibre_targets_by_inverse_kinematics_and_handedness():
    xy = [(np.array(b) + _fibre(a, be)).tolist() for b, (a, be) in zip(BASES, SPREAD)]
    p = _problem({"alpha_beta_deg": FOLDED}, {"xy_mm": xy, "handedness": "right"})
    assert np.abs(p.angles_deg(p.target) - np.array(SPREAD)).max() < 1e-9
    fibres = [p.kin(i).fibre(p.target[i].astype(float)) + BASES[i] for i in range(3)]
    assert np.abs(np.array(fibres) - np.array(xy)).max() < 1e-9
    # the left-handed elbow has beta < 0: outside [0, 180], a one-line error naming robot and values
    with pytest.raises(InputError, match=r"target.xy_mm\[0\]: the left-handed solution .* outside the joint ranges"):
        _problem({"alpha_beta_deg": FOLDED}, {"xy_mm": xy, "handedness": "left"})
    assert np.abs(_problem({"alpha_beta_deg": FOLDED}, {"xy_mm": xy}).angles_deg(p.target) - SPREAD).max() < 1e-9


@pytest.mark.parametrize("start, target, kin, error, needle", [
    ({"alpha_beta_deg": FOLDED}, {"xy_mm": [[40.0, 0.0], [22.4, 10.0], [11.2, 30.0]]}, None, InputError,
     r"target.xy_mm\[0\]: fibre position \[40.0, 0.0\] is 40.000 mm from the robot's base, outside its reach "
     r"\[7.600, 22.400\] mm"),
    ({"alpha_beta_deg": [[10, 170], [10, 190], [10, 170]]}, {"alpha_beta_deg": SPREAD}, None, InputError,
     r"start.alpha_beta_deg\[1\]: beta 190 deg is outside the beta range \[0, 180\]"),
    ({"alpha_beta_deg": [[10, 170], [10, 170], [-5, 170]]}, {"alpha_beta_deg": SPREAD}, dict(KIN, alpha_range=[0, 360]),
     InputError, r"start.alpha_beta_deg\[2\]: alpha -5 deg is outside the alpha range \[0, 360\]"),
    ({"alpha_beta_deg": FOLDED[:2]}, {"alpha_beta_deg": SPREAD}, None, FormatError,
     r"start.alpha_beta_deg must be a list of 3 pairs, got 2 entries"),
    ({"alpha_beta_deg": [[10, "x"]] * 3}, {"alpha_beta_deg": SPREAD}, None, FormatError,
     r"start.alpha_beta_deg\[0\] must be a pair of finite numbers"),
    ({"alpha_beta_deg": FOLDED, "xy_mm": []}, {"alpha_beta_deg": SPREAD}, None, FormatError, "exactly one of"),
    ({"alpha_beta_deg": FOLDED}, {"xy_mm": [[1, 1]] * 3, "handedness": "up"}, None, InputError,
     "target.handedness must be one of right, left, any"),
])
def test_bad_angles_are_one_line_errors(start, target, kin, error, needle):
    with pytest.raises(error, match=needle) as info:
        _problem(start, target, kin)
    assert info.value.where == "p.json" and "\n" not in str(info.value)


def test_rotary_has_no_angle_forms():
    rot = {"kind": "rotary", "arm": 10.0, "steps": 8}
    with pytest.raises(InputError, match="start.alpha_beta_deg needs alpha-beta kinematics"):
        _problem({"alpha_beta_deg": FOLDED}, [0, 0, 0], rot)
    with pytest.raises(InputError, match="offline needs alpha-beta kinematics"):
        _problem([0, 0, 0], [0, 0, 0], rot, offline={"0": [10, 170]})


def test_alpha_hard_stops_do_not_wrap():
    kin = AlphaBeta(7.4, 15.0, 5, 3, (0.0, 180.0), alpha_range=(0.0, 360.0))
    assert not kin.joints[0].wraps
    assert kin.lattice_deg(0).tolist() == [0.0, 90.0, 180.0, 270.0, 360.0]
    assert kin.step([4, 0], 0, +1) is None and kin.step([0, 0], 0, -1) is None
    p = _problem([[0, 6], [0, 6], [0, 6]], [[11, 6], [11, 6], [11, 6]], dict(KIN, alpha_range=[0, 360]))
    from supcoord.problems.plan import lower_bound
    assert lower_bound(p) == 11  # no way round through 360 -> 0
    with pytest.raises(InputError, match="alpha_range must satisfy"):
        AlphaBeta(7.4, 15.0, 5, 3, alpha_range=(10.0, 5.0))


def test_margin_grows_every_buffer_sum():
    base = _problem({"alpha_beta_deg": FOLDED}, {"alpha_beta_deg": SPREAD})
    wide = _problem({"alpha_beta_deg": FOLDED}, {"alpha_beta_deg": SPREAD}, collision={"buffer": 2.0, "margin": 0.78})
    assert np.allclose(wide.buffers[:, None] + wide.buffers[None, :] - base.buffers[:, None] - base.buffers[None, :],
                       0.78)
    assert wide.to_json()["collision"] == {"buffer": 2.0, "margin": 0.78}
    with pytest.raises(InputError, match=r"collision.margin must be a number of mm in \[0, 1e6\], got -1"):
        _problem([[0, 0]] * 3, [[0, 0]] * 3, collision={"buffer": 2.0, "margin": -1})
