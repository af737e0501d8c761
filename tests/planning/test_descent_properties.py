"""The public descent (:func:`supcoord.planning.descent.descent`) against opinions of its own:
robots too far apart to meet walk straight to their targets, one lattice step per joint per
step the short way round (counted here from the lattice), the step limit and the progress
callback cut the same descent short, and on crowded lattices with unequal buffers every
step passes the validator as one simultaneous motion and in every order of its moves.
Written for mutants of ``descent.py`` (mutation testing: ``benchmarks/mutation_run.py descent``).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from supcoord.planning.descent import descent, descent_step
from supcoord.problems import Plan, parse_problem, random_problem, validate_plan

AB = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}
ROT = {"kind": "rotary", "arm": 15.0, "steps": 12}
LATTICE = {"alpha-beta": (12, 7), "rotary": (12,)}
WRAPS = {"alpha-beta": (True, False), "rotary": (True,)}


def _far_apart(kin, start, target):
    """Robots 500 mm apart: nothing can meet, every move is free."""
    xy = [[500.0 * i, 0.0] for i in range(len(start))]
    if kin["kind"] == "rotary":  # one integer a robot
        start, target = [s[0] for s in start], [t[0] for t in target]
    data = {"layout": {"kind": "points", "xy": xy}, "kinematics": kin, "collision": {"buffer": 1.0},
            "start": start, "target": target}
    return parse_problem(data)


def _lattice_distance(kind, a, b):
    """Per joint: positions apart, the short way round on a wrapping joint."""
    out = []
    for n, wraps, x, y in zip(LATTICE[kind], WRAPS[kind], a, b):
        d = abs(x - y)
        out.append(min(d, n - d) if wraps else d)
    return out


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("kin", [AB, ROT], ids=["alpha-beta", "rotary"])
def test_free_robots_walk_straight_to_their_targets(kin, seed):
    rng = np.random.default_rng(seed)
    sizes = LATTICE[kin["kind"]]
    start = [[int(rng.integers(n)) for n in sizes] for _ in range(3)]
    target = [[int(rng.integers(n)) for n in sizes] for _ in range(3)]
    target[0] = list(start[0])  # one robot already there
    if len(sizes) == 1:
        target[1] = [(start[1][0] + 6) % 12]  # half a turn: either way is the short way
    p = _far_apart(kin, start, target)
    dist = [_lattice_distance(kin["kind"], s, t) for s, t in zip(start, target)]
    steps, end = descent(p, p.start)
    assert np.array_equal(end, p.target)
    assert len(steps) == max(max(d) for d in dist)
    c = [list(s) for s in start]
    for k, step in enumerate(steps):
        # every robot still off target moves every joint still off target, one position nearer
        want = {(r, j) for r in range(3) for j, d in enumerate(dist[r]) if d > k}
        assert {(r, j) for r, j, _ in step} == want and len(step) == len(want)
        assert [r for r, _, _ in step] == sorted(r for r, _, _ in step)  # in priority (= index) order
        for r, j, d in step:
            before = _lattice_distance(kin["kind"], c[r], target[r])[j]
            c[r][j] = (c[r][j] + d) % sizes[j]
            assert _lattice_distance(kin["kind"], c[r], target[r])[j] == before - 1
    assert descent_step(p, end) == []  # at target: nothing to do


def test_the_step_limit_and_the_callback_cut_the_same_descent_short():
    p = _far_apart(AB, [[0, 0], [3, 6]], [[6, 6], [9, 0]])
    start = p.start.copy()
    full, end = descent(p, p.start)
    assert len(full) == 6 and np.array_equal(p.start, start)  # the start is not changed
    seen = []
    part, mid = descent(p, p.start, max_steps=2, check=lambda stage, **info: seen.append((stage, info)))
    assert part == full[:2]
    assert seen == [("descent", {"iteration": 0}), ("descent", {"iteration": 1})]
    c = start.copy()
    for step in part:
        for r, j, d in step:
            c[r][j] += d
    assert np.array_equal(mid, c)  # no joint crosses the wrap on this way
    assert descent(p, p.start, max_steps=0)[0] == []


def _single_steps_valid(p, c, step, order):
    x = c.copy()
    for r, j, d in order:
        nxt = x.copy()
        nxt[r] = p.kinematics.step(x[r], j, d)
        one = dataclasses.replace(p, start=x, target=nxt)
        if not validate_plan(one, Plan("complete", [x, nxt])).valid:
            return False
        x = nxt
    return True


@pytest.mark.slow  # 3-10 s each on a loaded 2-core machine (the tables of a hexagon)
@pytest.mark.parametrize("seed,buffer", [(0, 0.5), (1, 3.0)])
def test_crowded_descent_steps_pass_the_validator(seed, buffer):
    """Tight hexagons: each step is valid as one simultaneous motion (the validator), the
    first ones also move by move in reverse order; the descent never moves a robot away."""
    kin = dict(AB, alpha_steps=8, beta_steps=5)
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, kin, buffer, seed=seed)
    steps, end = descent(p, p.start)
    c = p.start.copy()
    dist = p.kinematics.joint_distance
    for k, step in enumerate(steps):
        if k < 2:
            assert _single_steps_valid(p, c, step, step[::-1]), step
        nxt = c.copy()
        for r, j, d in step:
            nxt[r] = p.kinematics.step(nxt[r], j, d)
        assert np.sum(dist(nxt, p.target)) < np.sum(dist(c, p.target))
        c = nxt
    assert np.array_equal(c, end)
    confs = [p.start.copy()]
    for step in steps:
        confs.append(confs[-1].copy())
        for r, j, d in step:
            confs[-1][r] = p.kinematics.step(confs[-1][r], j, d)
    whole = dataclasses.replace(p, target=end)
    assert validate_plan(whole, Plan("complete", confs)).valid  # every step as one simultaneous motion



@pytest.mark.parametrize("side", [0, 1])
def test_motion_free_is_the_swept_check_of_the_two_robots_it_names(side):
    """Two robots of different arm lengths: ``motion_free`` of pair 0 with member ``side`` turning
    and the other standing agrees with the exact swept check of one turn
    (:func:`supcoord.geometry.motion.motion_collides`) of that member's arm, each robot with its
    own kinematics, for every pose and turn: never free where the turn collides, and free
    wherever it keeps ``tol`` more than the buffers (the certificate's documented slack)."""
    from supcoord.geometry.kinematics import Rotary
    from supcoord.geometry.motion import DEFAULT_TOL, motion_collides
    from supcoord.planning.descent import motion_free

    xy = [[0.0, 0.0], [19.0, 0.0]]
    data = {"layout": {"kind": "points", "xy": xy}, "kinematics": ROT, "collision": {"buffer": 1.0},
            "start": [0, 0], "target": [0, 0]}
    p = dataclasses.replace(parse_problem(data, check_collisions=False),
                            robot_kinematics=[Rotary(15.0, 12), Rotary(7.0, 12)])
    a, b = (int(v) for v in p.pairs[0])
    mover, other = (a, b) if side == 0 else (b, a)
    x, dx, y, dy = (np.array(v).reshape(-1, 1) for v in zip(*[(x, dx, y, dy) for x in range(12) for dx in (-1, 1)
                                                             for y in range(12) for dy in (0,)]))
    free, clear = (~motion_collides(p.kin(mover), p.bases[mover], x, dx, p.kin(other), p.bases[other], y, dy,
                                    p.buffers[a] + p.buffers[b] + extra) for extra in (0.0, DEFAULT_TOL))
    got = np.array([motion_free(p, 0, side, x[i], dx[i], y[i], None) for i in range(len(x))])
    assert not (got & ~free).any() and not (clear & ~got).any()
    # poses and turns given as Python sequences (its annotation's other form) read the same
    assert [motion_free(p, 0, side, x[i].tolist(), tuple(dx[i]), list(y[i]), [0]) for i in range(0, len(x), 7)] \
        == got[::7].tolist()
    assert 0 < clear.sum() and free.sum() < len(got)


@pytest.mark.parametrize("seed", [0, 4])
def test_the_descent_on_lazy_tables_is_the_descent_on_whole_tables(monkeypatch, seed):
    """Entries decided as they are read (lazy tables) give the same descent, step for step,
    as the whole tables built first."""
    from supcoord.geometry import collision
    from supcoord.problems.presets import preset_problem

    whole = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5, seed=seed)
    assert not whole.tables().lazy
    monkeypatch.setattr(collision, "LAZY_TABLE_BYTES", 0)
    lazy = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5, seed=seed)
    assert lazy.tables().lazy
    steps, end = descent(whole, whole.start)
    got_steps, got_end = descent(lazy, lazy.start)
    assert steps and got_steps == steps and np.array_equal(got_end, end)
