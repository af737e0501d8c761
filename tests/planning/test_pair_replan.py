"""Two neighbours re-planned together (:mod:`supcoord.planning.pair_replan`) against an explicit
breadth-first search of the pair's product space that shares none of its shortcuts (no
separable image of the states far apart, no pruning by arrival in time, parents kept for
every state): the same earliest arrival and the same trajectories, step for step."""

from __future__ import annotations

import numpy as np
import pytest

import supcoord
from supcoord.geometry.motion import motion_collides
from supcoord.planning.improve import _Replanner
from supcoord.planning.pair_replan import _alone, pair_replan
from supcoord.problems.presets import preset_problem


def explicit_pair_search(rp, r, b, k, horizon, before):
    """Layer by layer over sets of pair states; each step of the two checked by
    :func:`motion_collides` itself; a state's parent is the first of (option of ``r``, option
    of ``b``, row, column) with a free step into it."""
    problem, nxt, deltas = rp.problem, rp.nxt, np.asarray(rp.deltas)
    goals = (int(rp.kin.flat_index(problem.target[r])), int(rp.kin.flat_index(problem.target[b])))
    (stay_r, masks_r), (stay_b, masks_b) = _alone(rp, r, b, goals[0], horizon), _alone(rp, b, r, goals[1], horizon)
    layer = {(int(rp.traj[0, r]), int(rp.traj[0, b])): None}
    history = []
    for t in range(min(before, horizon + 1)):
        if goals in layer and stay_r[t] and stay_b[t]:
            path = [goals]
            for parents in reversed(history):
                path.append(parents[path[-1]])
            path.reverse()
            out = []
            for x, column in ((r, [s[0] for s in path]), (b, [s[1] for s in path])):
                traj = rp.traj[:, x].copy()
                traj[:len(path)] = column
                traj[len(path):] = column[-1]
                out.append(traj)
            return out
        if t == horizon:
            return None
        cand = [(u, v, i, j) for u in range(len(deltas)) for v in range(len(deltas)) for (i, j) in sorted(layer)
                if masks_r[t][u][i] and masks_b[t][v][j]]
        if not cand:
            return None
        u, v, i, j = (np.array(c) for c in zip(*cand))
        hit = motion_collides(problem.kin(r), problem.bases[r], rp.pos[i], deltas[u], problem.kin(b), problem.bases[b],
                              rp.pos[j], deltas[v], float(problem.buffers[r] + problem.buffers[b]))
        parents = {}
        for x in np.flatnonzero(~hit):
            parents.setdefault((int(nxt[u[x], i[x]]), int(nxt[v[x], j[x]])), (int(i[x]), int(j[x])))
        history.append(parents)
        layer = parents
    return None


@pytest.mark.parametrize("seed", [5])
def test_the_pair_search_equals_the_explicit_search(seed):
    p = preset_problem("sdss-v", rings=1, seed=seed, alpha_steps=9, beta_steps=5)
    plan = supcoord.solve(p, improve=0, validation="none", simultaneous=None, finer=None)
    assert plan.status == "complete"
    rp = _Replanner(p, [np.asarray(c) for c in plan.configurations], {"replans": 0})
    horizon = len(rp.traj) - 1
    found = tried = 0
    for r in range(p.n):
        for k, b, side in rp.nbrs[r]:
            for before in (max(rp.finish(r), rp.finish(b)),) if b < r else (horizon + 1,):
                got = pair_replan(rp, r, b, k, side, horizon, before)
                want = explicit_pair_search(rp, r, b, k, horizon, before)
                tried += 1
                assert (got is None) == (want is None), (r, b, before)
                if want is not None:
                    found += 1
                    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1]), (r, b, before)
    assert tried >= 12 and found >= 3, (tried, found)



def _replanner(seed, steps=(9, 5)):
    p = preset_problem("sdss-v", rings=1, seed=seed, alpha_steps=steps[0], beta_steps=steps[1])
    plan = supcoord.solve(p, improve=0, validation="none", simultaneous=None, finer=None)
    return p, _Replanner(p, [np.asarray(c) for c in plan.configurations], {"replans": 0})


def test_one_step_of_the_pair_equals_the_explicit_image_from_any_states():
    """:func:`_layer` (the states far apart stepped as rows then columns, the near ones one by
    one) from random sets of collision-free pair states: the states :func:`motion_collides`
    lets the two reach in one step."""
    from supcoord.planning.pair_replan import _layer, _PairMotions

    p, rp = _replanner(5, (24, 13))  # fine enough for states too far apart to collide in one step
    rng = np.random.default_rng(0)
    npos, deltas = len(rp.pos), np.asarray(rp.deltas)
    checked = pairs = 0
    for r in (0, 1):
        for k, b, side in rp.nbrs[r][:2]:
            motions = _PairMotions(rp, r, b, k, side)
            masks_r, masks_b = rp.layer_masks(r)[0], rp.layer_masks(b)[0]
            bsum = float(p.buffers[r] + p.buffers[b])
            ii, jj = (g.ravel() for g in np.meshgrid(np.arange(npos), np.arange(npos), indexing="ij"))
            apart = ~motion_collides(p.kin(r), p.bases[r], rp.pos[ii], deltas[0], p.kin(b), p.bases[b], rp.pos[jj],
                                     deltas[0], bsum).reshape(npos, npos)
            reach = apart & (rng.random((npos, npos)) < 0.05)
            got = _layer(rp, motions, reach, masks_r, masks_b)
            want = np.zeros_like(reach)
            si, sj = np.nonzero(reach)
            for u in range(len(deltas)):
                for v in range(len(deltas)):
                    ok = masks_r[u][si] & masks_b[v][sj]
                    i, j = si[ok], sj[ok]
                    hit = motion_collides(p.kin(r), p.bases[r], rp.pos[i], deltas[u], p.kin(b), p.bases[b], rp.pos[j],
                                          deltas[v], bsum)
                    want[rp.nxt[u, i[~hit]], rp.nxt[v, j[~hit]]] = True
            assert np.array_equal(got, want), (r, b, int((got != want).sum()))
            pairs += 1
            checked += int(0 < motions.near.sum() < npos * npos) + int(reach.sum() > 0)
    assert pairs >= 2 and checked == 2 * pairs, (pairs, checked)


def test_the_steps_kept_are_those_after_which_the_robot_still_arrives_in_time():
    """:func:`_in_time` against its definition, by a search from each step and position: the
    robot alone can be at its goal at a step ``t' ≤ last`` from which it may stand there."""
    from supcoord.planning.pair_replan import _in_time

    p, rp = _replanner(5)
    horizon = len(rp.traj) - 1
    for r, b in ((r, rp.nbrs[r][0][1]) for r in range(p.n)):
        goal = int(rp.kin.flat_index(p.target[r]))
        stay, masks = _alone(rp, r, b, goal, horizon)
        for last in range(1, horizon + 1):
            got = _in_time(rp, masks, stay, goal, last)

            def arrives(t, i, memo={}):
                key = (last, t, i)
                if key not in memo:
                    memo[key] = (i == goal and bool(stay[t])) or (t < last and any(
                        masks[t][u][i] and rp.nxt[u, i] >= 0 and arrives(t + 1, int(rp.nxt[u, i]))
                        for u in range(len(rp.deltas))))
                return memo[key]

            for t in range(len(masks)):
                for u in range(len(rp.deltas)):
                    for i in range(len(rp.pos)):
                        want = t < last and bool(masks[t][u][i]) and rp.nxt[u, i] >= 0 and arrives(t + 1, int(rp.nxt[u, i]))
                        assert bool(got[t][u][i]) == want, (r, last, t, u, i)
