"""Two neighbours re-planned together in space-time: the joint neighbourhood of plan improvement.

:mod:`.improve` re-plans positioners one at a time, each around the fixed trajectories of
the others.  Two neighbours that are each in the other's way (one must step aside while
the other passes) defeat that: whichever is planned first takes the straight path, and
the second can no longer arrive.  Planning the pair at once finds the plan in which they
give way to each other.  With ``τ_q`` the fixed trajectories of every other positioner::

    R(0) = {(start_r, start_b)},
    R(t+1) = {(i + u, j + v) : (i, j) ∈ R(t), u, v ∈ the options of a step (stand, one joint, several),
              r doing u from i is free against every other neighbour's step τ_q(t) → τ_q(t+1)
              (and its own constraints), likewise b doing v from j,
              and r doing u from i while b does v from j is free}

(the last test is the certified motion
:func:`~supcoord.geometry.motion.prefiltered_motion_collides`, computed for the states
reached only and kept for the pair: both moving linearly over the same step, the
validator's interpolation, exact where one turns one joint past the other standing); the pair's new trajectories are the
earliest ``t`` with ``(target_r, target_b) ∈ R(t)`` from which both may stand at their
targets to the plan's end, read back through the parents of each layer.  Each step of
either was checked against every other trajectory of the plan in that very step and
against the other's, so the plan stays valid.  The state space is the pair's product of
positions (``91² = 8,281`` on a 13 × 7 lattice, ``684² = 467,856`` on 36 × 19), one boolean
layer per step.  Two shortcuts keep a layer's cost near that of its states, not of its
states times the 81 option pairs, with the same result: the states where the two are too
far apart for any step of theirs to collide are stepped as a whole (``r``'s options applied
to the rows, then ``b``'s to the columns), and each robot's options are kept only where it
can still arrive in time alone (:func:`_in_time`).  Parents are read back for the path only.

Reference
---------
- G. Wagner, H. Choset, Subdimensional expansion for multirobot path planning, Artificial
  Intelligence 219, 2015 (planning coupled robots jointly, only where they interact).
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any

import numpy as np

from ..geometry.motion import prefiltered_motion_collides

__all__ = ["pair_replan", "PAIR_STATES", "PAIRS_KEPT"]

#: the largest product of two robots' positions re-planned together (``1,000²``: a 37 × 19
#: lattice's 703² = 494,209 is, the APO wok's 73 × 37 = 2,701² is not: a boolean layer of
#: 7.3 million states per step and 81 motion entries per state pair to remember)
PAIR_STATES = 1_000_000
#: the pairs whose motion verdicts are kept for their next re-plans (the latest used): a pair's
#: table has ``options² · positions²`` entries, 38 MB on a 36 × 19 lattice (9² · 684²), so
#: keeping every pair's grew with the number of pairs re-planned; a pair's verdicts are
#: decided entry by entry, so one dropped and computed again gives the same Booleans
PAIRS_KEPT = 8


def pair_replan(rp: Any, r: int, b: int, k: int, side: int, horizon: int,
                before: int) -> tuple[np.ndarray, np.ndarray] | None:
    """New trajectories ``(τ_r, τ_b)`` (length ``horizon + 1``) of neighbours ``r`` and ``b``
    (pair ``k`` of the problem, ``side`` = ``r``'s) planned together (module docstring), if
    both arrive before step ``before``; ``rp``: the :mod:`.improve` re-planner holding the
    plan's trajectories (its ``layer_masks`` and ``stay_from`` with ``absent`` honoured).
    None too where the pair's product of positions exceeds :data:`PAIR_STATES` (not tried)."""
    npos = len(rp.pos)
    if npos * npos > PAIR_STATES:
        return None
    motions = _PairMotions(rp, r, b, k, side)
    goals = (int(rp.kin.flat_index(rp.problem.target[r])), int(rp.kin.flat_index(rp.problem.target[b])))
    (stay_r, masks_r), (stay_b, masks_b) = _alone(rp, r, b, goals[0], horizon), _alone(rp, b, r, goals[1], horizon)
    last = min(before, horizon + 1) - 1  # the last step at which both may arrive
    masks_r, masks_b = _in_time(rp, masks_r, stay_r, goals[0], last), _in_time(rp, masks_b, stay_b, goals[1], last)
    reach = np.zeros((npos, npos), dtype=bool)
    reach[int(rp.traj[0, r]), int(rp.traj[0, b])] = True
    layers: list[np.ndarray] = []  # the states reached before each step
    for t in range(last + 1):
        if reach[goals] and stay_r[t] and stay_b[t]:
            return _read_back(rp, motions, r, b, goals, layers, masks_r, masks_b)
        if t == horizon:
            return None
        layers.append(reach)
        reach = _layer(rp, motions, reach, masks_r[t], masks_b[t])
        if not reach.any():
            return None
    return None


def _in_time(rp: Any, masks: np.ndarray, stay: np.ndarray, goal: int, last: int) -> np.ndarray:
    """``masks`` (``[t, u, i]``, one robot's) restricted to the steps that end where the robot,
    alone, can still arrive in time: at ``goal`` at some step ``t' ≤ last`` with ``stay[t']``.

    A pair state that either robot cannot leave in time reaches no goal of the pair, and no
    state on a path to the goal is left out (each step of such a path ends where both
    arrive in time), so the pair's search finds the same trajectories through the same
    parents on fewer states: around the plan being shortened the robots have little slack."""
    nxt = rp.nxt
    valid = nxt >= 0
    target = np.zeros(masks.shape[-1], dtype=bool)
    target[goal] = True
    out = np.zeros_like(masks)
    ok = target & bool(stay[last])  # where the robot may be at step t + 1
    for t in range(min(last, len(masks)) - 1, -1, -1):
        out[t] = masks[t] & valid & ok[np.where(valid, nxt, 0)]
        ok = out[t].any(axis=0) | (target & bool(stay[t]))
    return out


def _alone(rp: Any, x: int, other: int, goal: int, horizon: int) -> tuple[Any, np.ndarray]:
    """``(stay, masks)`` of ``x`` against every trajectory but ``other``'s: whether it may stand
    at ``goal`` from step ``t`` on (``stay[t]``), and ``masks[t][u]``: the positions from which
    it may do option ``u`` during step ``t``."""
    saved = set(rp.absent)
    try:
        rp.absent = saved | {other}
        stay = rp.stay_from(x, goal, horizon)
        masks = rp.layer_masks(x)
    finally:
        rp.absent = saved
    return stay, masks


class _PairMotions:
    """Whether ``r`` and ``b`` moving together over one step is free, for the entries asked
    (:func:`~supcoord.geometry.motion.prefiltered_motion_collides`), remembered in the
    re-planner's cache for the pair's next calls (the :data:`PAIRS_KEPT` latest pairs).

    ``near[i, j]``: the pair states from which some step of the two may collide.  Every point
    of ``r`` doing option ``u`` and of ``b`` doing ``v`` moves at most ``L_uv`` mm (the two sweep
    lengths), so the segments' distance changes by at most ``L_uv`` over the step: where the
    distance ``d0`` at the state is at least ``r_sum + max L_uv + MARGIN``, both end distances
    are at least ``r_sum`` and ``(d0 + d1 − L_uv)/2 ≥ r_sum`` for every ``(u, v)``, so the
    end-point prefilter of :func:`~supcoord.geometry.motion.prefiltered_motion_collides` finds
    every step of the two free there (the margin covers the distances' rounding)."""

    #: slack (mm) above the Lipschitz bound for the rounding of computed distances
    MARGIN = 1e-6

    def __init__(self, rp: Any, r: int, b: int, k: int, side: int):
        self.rp, self.r, self.b = rp, r, b
        problem = rp.problem
        dist = rp.tables.distance_view(k)
        self.dist = dist if side == 0 else dist.T  # [position of r, position of b]
        self.bsum = float(problem.buffers[r] + problem.buffers[b])
        self.deltas = np.asarray(rp.deltas)
        npos, n_opt = len(rp.pos), len(rp.deltas)
        kept = rp.merged_cache.setdefault("pairs", OrderedDict())  # the latest pairs' tables, oldest first
        known, near = kept.pop((k, side), (None, None))
        if known is None:
            known = np.zeros((n_opt, n_opt, npos, npos), dtype=np.int8)  # 0: not computed yet, 1 free, 2 collides
            reach = float(problem.kin(r).sweep_length(self.deltas).max() + problem.kin(b).sweep_length(self.deltas).max())
            ii, jj = np.meshgrid(np.arange(npos), np.arange(npos), indexing="ij")
            near = np.asarray(self.dist[ii.ravel(), jj.ravel()]).reshape(npos, npos) < self.bsum + reach + self.MARGIN
        kept[k, side] = (known, near)
        while len(kept) > PAIRS_KEPT:
            kept.popitem(last=False)
        self.known, self.near = known, near

    def free(self, u: np.ndarray, v: np.ndarray, ii: np.ndarray, jj: np.ndarray) -> np.ndarray:
        """Is ``r`` doing ``u`` from ``ii`` while ``b`` does ``v`` from ``jj`` free (entries)?"""
        rp, problem, known, r, b = self.rp, self.rp.problem, self.known, self.r, self.b
        state = known[u, v, ii, jj]
        todo = np.nonzero(state == 0)[0]
        if len(todo):
            u, v, ii, jj = u[todo], v[todo], ii[todo], jj[todo]
            hit = prefiltered_motion_collides(problem.kin(r), problem.bases[r], rp.pos, ii, rp.nxt[u, ii],
                                              self.deltas[u], problem.kin(b), problem.bases[b], jj, rp.nxt[v, jj],
                                              self.deltas[v], self.bsum, self.dist)
            state[todo] = known[u, v, ii, jj] = np.where(hit, 2, 1)
        return state == 1


def _layer(rp: Any, motions: _PairMotions, reach: np.ndarray, masks_r: np.ndarray,
           masks_b: np.ndarray) -> np.ndarray:
    """The pair states one step after ``reach``: from the states far apart
    (:attr:`_PairMotions.near` false) every step allowed to each alone is free together, so
    their successors are ``r``'s options applied to the rows, then ``b``'s to the columns; the
    steps from the near states are checked one by one (:meth:`_PairMotions.free`)."""
    npos, n_opt, nxt = len(rp.pos), len(rp.deltas), rp.nxt
    new = np.zeros((npos, npos), dtype=bool)
    far = reach & ~motions.near
    if far.any():
        rows = np.zeros((npos, npos), dtype=bool)  # after r's option: [r's new position, b's old]
        occupied = far.any(axis=1)
        for u in range(n_opt):
            src = np.nonzero(masks_r[u] & occupied)[0]
            _or_into(rows, nxt[u, src], far[src])
        occupied = rows.any(axis=0)
        for v in range(n_opt):
            src = np.nonzero(masks_b[v] & occupied)[0]
            _or_into(new.T, nxt[v, src], rows[:, src].T)
    ii, jj = np.nonzero(reach & motions.near)
    if len(ii):
        parts = []
        for u in range(n_opt):
            from_r = masks_r[u][ii]
            if from_r.any():
                for v in range(n_opt):
                    sel = np.nonzero(from_r & masks_b[v][jj])[0]
                    parts.append((np.full(len(sel), u), np.full(len(sel), v), ii[sel], jj[sel]))
        uu, vv, si, sj = (np.concatenate(x) for x in zip(*parts)) if parts else (np.zeros(0, np.int64),) * 4
        free = motions.free(uu, vv, si, sj)
        new[nxt[uu[free], si[free]], nxt[vv[free], sj[free]]] = True
    return new


def _or_into(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """``out[rows[x]] |= values[x]`` for every ``x``, repeated rows included."""
    if len(np.unique(rows)) == len(rows):
        out[rows] |= values
    else:
        np.logical_or.at(out, rows, values)


def _parent(rp: Any, motions: _PairMotions, state: tuple[int, int], reach: np.ndarray, mask_r: np.ndarray,
            mask_b: np.ndarray) -> tuple[int, int]:
    """The state of ``reach`` that ``state`` is reached from: the first in (option of ``r``, option
    of ``b``, row, column) order among those with a free step into it."""
    nxt = rp.nxt
    for u in range(len(rp.deltas)):
        src_i = np.nonzero((nxt[u] == state[0]) & mask_r[u])[0]
        if not len(src_i):
            continue
        for v in range(len(rp.deltas)):
            src_j = np.nonzero((nxt[v] == state[1]) & mask_b[v])[0]
            ii, jj = (g.ravel() for g in np.meshgrid(src_i, src_j, indexing="ij"))
            sel = reach[ii, jj]
            ii, jj = ii[sel], jj[sel]
            if len(ii):
                free = motions.free(np.full(len(ii), u), np.full(len(ii), v), ii, jj)
                if free.any():
                    x = int(np.argmax(free))
                    return int(ii[x]), int(jj[x])
    raise AssertionError(f"pair state {state} has no parent")  # pragma: no cover - reach is its image


def _read_back(rp: Any, motions: _PairMotions, r: int, b: int, goals: tuple[int, int], layers: list[np.ndarray],
               masks_r: np.ndarray, masks_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pair's trajectories arriving at ``goals`` after ``len(layers)`` steps, read back
    through each step's parents (:func:`_parent`); every later step stands at the goal."""
    path = [goals]
    for t in range(len(layers) - 1, -1, -1):
        path.append(_parent(rp, motions, path[-1], layers[t], masks_r[t], masks_b[t]))
    path.reverse()
    arrival = len(layers)
    out = []
    for x, column in ((r, np.array([p[0] for p in path])), (b, np.array([p[1] for p in path]))):
        traj = rp.traj[:, x].copy()
        traj[:arrival + 1] = column
        traj[arrival + 1:] = column[-1]
        out.append(traj)
    return out[0], out[1]
