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
positions (``91² = 8,281`` on a 13 × 7 lattice), one boolean layer per step.

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
    reach = np.zeros((npos, npos), dtype=bool)
    reach[int(rp.traj[0, r]), int(rp.traj[0, b])] = True
    parents: list[np.ndarray] = []
    for t in range(min(before, horizon + 1)):
        if reach[goals] and stay_r[t] and stay_b[t]:
            return _read_back(rp, r, b, goals, parents)
        if t == horizon:
            return None
        par, reach = _layer(rp, motions, reach, masks_r[t], masks_b[t])
        parents.append(par)
        if not reach.any():
            return None
    return None


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
    re-planner's cache for the pair's next calls (the :data:`PAIRS_KEPT` latest pairs)."""

    def __init__(self, rp: Any, r: int, b: int, k: int, side: int):
        self.rp, self.r, self.b = rp, r, b
        problem = rp.problem
        dist = rp.tables.distance_view(k)
        self.dist = dist if side == 0 else dist.T  # [position of r, position of b]
        self.bsum = float(problem.buffers[r] + problem.buffers[b])
        self.deltas = np.asarray(rp.deltas)
        npos, n_opt = len(rp.pos), len(rp.deltas)
        kept = rp.merged_cache.setdefault("pairs", OrderedDict())  # the latest pairs' tables, oldest first
        known = kept.pop((k, side), None)  # 0: not computed yet, 1 free, 2 collides
        if known is None:
            known = np.zeros((n_opt, n_opt, npos, npos), dtype=np.int8)
        kept[k, side] = known
        while len(kept) > PAIRS_KEPT:
            kept.popitem(last=False)
        self.known = known

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
           masks_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(parents, reach')``: the pair states one step after ``reach`` and the parent of each
    (flat ``i · P + j``, −1 where none: the first in option order)."""
    npos, n_opt = len(rp.pos), len(rp.deltas)
    par = np.full(npos * npos, -1, dtype=np.int64)
    new = np.zeros(npos * npos, dtype=bool)
    parts = []
    for u in range(n_opt):
        from_r = reach & masks_r[u][:, None]
        if from_r.any():
            for v in range(n_opt):
                ii, jj = np.nonzero(from_r & masks_b[v][None, :])
                parts.append((np.full(len(ii), u), np.full(len(ii), v), ii, jj))
    if parts:
        uu, vv, ii, jj = (np.concatenate(x) for x in zip(*parts))
        free = motions.free(uu, vv, ii, jj)
        uu, vv, ii, jj = uu[free], vv[free], ii[free], jj[free]
        dst = rp.nxt[uu, ii] * npos + rp.nxt[vv, jj]
        first = np.unique(dst, return_index=True)[1]  # one parent per state: the first in option order
        par[dst[first]] = (ii * npos + jj)[first]
        new[dst] = True
    return par, new.reshape(npos, npos)


def _read_back(rp: Any, r: int, b: int, goals: tuple[int, int],
               parents: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The pair's trajectories arriving at ``goals`` after ``len(parents)`` steps, read back
    through the parents; every later step stands at the goal."""
    npos = len(rp.pos)
    path = [goals[0] * npos + goals[1]]
    for par in reversed(parents):
        path.append(int(par[path[-1]]))
    path.reverse()
    arrival = len(parents)
    out = []
    for x, column in ((r, np.asarray(path) // npos), (b, np.asarray(path) % npos)):
        traj = rp.traj[:, x].copy()
        traj[:arrival + 1] = column
        traj[arrival + 1:] = column[-1]
        out.append(traj)
    return out[0], out[1]
