"""When each robot makes each of its moves: the timing behind a plan's trajectories.

A plan is a sequence of configurations ``c_0 … c_T``; in step ``k`` robot ``p`` moves from
``c_k[p]`` to ``c_{k+1}[p]`` (a *move* ``(p, k)``, when the two differ), every joint turning
linearly in angle, and takes ``τ_{k,p} = max_j |Δθ_{k,p,j}| / v`` at joint speed ``v``.  The
planner certified each step with every robot moving at once along these straight lines,
each neighbour at its pose of the step.  Executed in lockstep, the plan takes
``Σ_k max_p τ_{k,p}``: every robot waits, at every step, for the slowest move of the whole
focal plane.  Only neighbours whose moves can actually meet need to keep the plan's order.

**Dependencies** (for every pair of neighbours ``p, q``, :attr:`Problem.pairs`, and every
move ``a`` of ``p`` and ``b`` of ``q``):

- ``a`` and ``b`` *apart*: their swept sets stay ``bsum`` apart at any times
  (:func:`supcoord.geometry.sweeps_apart.sweeps_apart`, certified; undecided counts as not
  apart).  No constraint.
- not apart, in steps ``k < k'``: ``b`` starts after ``a`` ends (an *order*).
- not apart, in the same step: ``a`` and ``b`` move over one common interval (*synchronised*),
  each joint at the constant velocity that fills it: the simultaneous motion the planner
  certified.  Synchronised moves form groups; a group lasts its longest move.

Each robot makes its moves in its own order, and every group starts as soon as the groups
it depends on (its robots' previous moves and its orders) have ended; ``motion_time_s`` is
the last end.  The constraints are a subset of those of the plan's steps run one after the
other, so the timing is never slower than lockstep.

**Why it is safe.**  Take neighbours ``p, q`` and a time when ``q`` makes move ``b`` (step
``k'``).  If ``p`` is moving too, its move ``a`` overlaps ``b`` in time, so the two are
neither ordered nor in different groups: they are synchronised (the certified step ``k'``)
or apart.  If ``p`` stands at the pose ``y`` between its moves ``a_i`` and ``a_{i+1}`` (or
before its first, after its last), then ``a_i`` ended before ``b`` started and ``a_{i+1}``
starts after ``b`` ends; each of them is apart from ``b`` (and ``y``, an end pose of it, is
in its swept set) or ordered with ``b`` in the direction of the steps, so when neither is
apart, ``step(a_i) < k' < step(a_{i+1})``: in step ``k'`` of the plan ``p`` stood at ``y``
while ``q`` made ``b``, which the planner certified.  Robots that stand, fixed obstacles,
joint rules and hard stops see only each robot's own poses, which the timing does not
change.  ``supcoord check`` verifies the resulting trajectories independently.

References
----------
- W. Hönig, T. K. S. Kumar, L. Cohen, H. Ma, H. Xu, N. Ayanian, S. Koenig, Multi-agent path
  finding with kinematic constraints, ICAPS 2016 (the temporal plan graph: execute a
  discrete plan by keeping only the orderings that matter).
- W. Hönig, S. Kiesel, A. Tinka, J. W. Durham, N. Ayanian, Persistent and robust execution
  of MAPF schedules in warehouses, IEEE Robotics and Automation Letters 4(2), 2019 (the
  action dependency graph).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..geometry.sweeps_apart import sweeps_apart
from .problem import Problem

__all__ = ["Timing", "plan_timing"]

#: pairs of moves decided per call of :func:`sweeps_apart` (about 40 MB of rows)
BLOCK = 1 << 17


@dataclass
class Timing:
    """The timing of a plan's moves (module docstring).

    ``step``, ``robot``: each move's step and robot (moves sorted by step, then robot);
    ``start``, ``end``: its interval (seconds); ``motion_time_s``: the last end (0 without
    moves); ``stats`` (PLAN.json ``stats.timing``): ``moves``, ``pairs`` (pairs of moves of
    neighbours examined), ``apart``, ``ordered``, ``synchronised`` (pairs of moves),
    ``lockstep_s`` (the plan run step after step)."""

    step: np.ndarray
    robot: np.ndarray
    start: np.ndarray
    end: np.ndarray
    motion_time_s: float
    stats: dict = field(default_factory=dict)


def plan_timing(problem: Problem, configurations, speed: float, angles: np.ndarray,
                duration: Callable[[np.ndarray], np.ndarray] | None = None) -> Timing:
    """The dependency timing (module docstring) of ``configurations`` at joint ``speed``
    (deg/s, checked by the caller), ``angles`` their continuous joint angles ``(T+1, N, J)``;
    ``duration`` (default ``|Δθ| / speed``) maps each move's largest joint turn (degrees) to
    its time (s), e.g. with acceleration ramps; it must be 0 exactly for no turn."""
    confs = np.asarray(configurations, dtype=np.int64)
    turn = np.abs(np.diff(angles, axis=0)).max(axis=2, initial=0.0)  # (T, N)
    own = turn / speed if duration is None else np.where(turn > 0, duration(turn), 0.0)
    step, robot = np.nonzero(own > 0)  # sorted by step, then robot
    duration = own[step, robot]
    n_moves = len(step)
    stats = {"moves": n_moves, "lockstep_s": float(own.max(axis=1, initial=0.0).sum())}
    if not n_moves:
        return Timing(step, robot, np.zeros(0), np.zeros(0), 0.0, dict(stats, pairs=0, apart=0, ordered=0,
                                                                          synchronised=0))
    # each robot's moves, in step order (np.nonzero sorts by step, the stable sort keeps it)
    by_robot = np.argsort(robot, kind="stable")
    moves_of = np.split(by_robot, np.searchsorted(robot[by_robot], np.arange(1, problem.n)))
    motions, lengths = _motions(problem, confs, step, moves_of)
    u, v = _neighbour_move_pairs(problem, moves_of)
    apart = np.zeros(len(u), dtype=bool)
    for lo in range(0, len(u), BLOCK):  # blocks bound the memory of the gathered rows
        a, b = u[lo:lo + BLOCK], v[lo:lo + BLOCK]
        apart[lo:lo + BLOCK] = sweeps_apart(motions[a], lengths[a], motions[b], lengths[b],
                                            problem.buffers[robot[a]] + problem.buffers[robot[b]])
    u, v = u[~apart], v[~apart]
    same = step[u] == step[v]
    early = np.where(step[u] < step[v], u, v)[~same]
    late = np.where(step[u] < step[v], v, u)[~same]
    stats.update(pairs=len(apart), apart=int(apart.sum()), ordered=int((~same).sum()), synchronised=int(same.sum()))
    n_groups, group = connected_components(
        coo_matrix((np.ones(int(same.sum())), (u[same], v[same])), shape=(n_moves, n_moves)), directed=False)
    # each robot's previous move comes first too
    follows = by_robot[1:][robot[by_robot[1:]] == robot[by_robot[:-1]]]
    precedes = by_robot[:-1][robot[by_robot[1:]] == robot[by_robot[:-1]]]
    src = np.concatenate([early, precedes])
    dst = np.concatenate([late, follows])
    start, end = _earliest(step, duration, group, n_groups, src, dst)
    return Timing(step, robot, start, end, float(end.max()), stats)


def _earliest(step: np.ndarray, duration: np.ndarray, group: np.ndarray, n_groups: int, src: np.ndarray,
              dst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each move's ``(start, end)``: step by step, a group starts at the latest end of its
    moves' predecessors (``src[i]`` before ``dst[i]``, always of an earlier step) and lasts
    its longest move."""
    order = np.argsort(step[dst], kind="stable")
    src, dst = src[order], dst[order]
    last = int(step[-1])
    bounds = np.searchsorted(step[dst], np.arange(last + 2))
    move_bounds = np.searchsorted(step, np.arange(last + 2))
    g_length = np.zeros(n_groups)
    np.maximum.at(g_length, group, duration)
    g_start = np.zeros(n_groups)
    ready = np.zeros(len(step))  # the latest end among each move's predecessors
    start, end = np.zeros(len(step)), np.zeros(len(step))
    for k in range(last + 1):
        lo, hi = bounds[k], bounds[k + 1]
        np.maximum.at(ready, dst[lo:hi], end[src[lo:hi]])
        m = np.arange(move_bounds[k], move_bounds[k + 1])
        np.maximum.at(g_start, group[m], ready[m])
        start[m] = g_start[group[m]]
        end[m] = start[m] + g_length[group[m]]
    return start, end


def _motions(problem: Problem, confs: np.ndarray, step: np.ndarray, moves_of: list[np.ndarray]
             ) -> tuple[np.ndarray, np.ndarray]:
    """Each move as a motion row (:data:`~supcoord.geometry.sweeps_apart.MOTION_FIELDS`) and its
    travel bound (:meth:`Kinematics.sweep_length`)."""
    kin = problem.kinematics
    deltas = np.stack([kin.signed_delta(confs[k], confs[k + 1]) for k in range(len(confs) - 1)])
    rows = np.empty((len(step), 11))
    lengths = np.empty(len(step))
    for p, m in enumerate(moves_of):
        if not len(m):
            continue
        kp = problem.kin(p)
        q, d = confs[step[m], p], deltas[step[m], p]
        a0, b0 = kp.chain_angles(q.astype(float))
        a1, b1 = kp.chain_angles((q + d).astype(float))
        l1, ((s0x, s0y), (s1x, s1y)) = kp.chain()
        rows[m, :7] = (problem.bases[p][0], problem.bases[p][1], l1, s0x, s0y, s1x, s1y)
        rows[m, 7:] = np.stack([a0, a1 - a0, b0, b1 - b0], axis=1)
        lengths[m] = kp.sweep_length(d.astype(float))
    return rows, lengths


def _neighbour_move_pairs(problem: Problem, moves_of: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Every pair ``(u, v)`` of moves of two neighbours (a pair of :attr:`Problem.pairs`);
    ``moves_of[p]``: robot ``p``'s moves."""
    us, vs = [], []
    for a, b in np.asarray(problem.pairs, dtype=np.int64).reshape(-1, 2).tolist():
        ma, mb = moves_of[a], moves_of[b]
        if len(ma) and len(mb):
            us.append(np.repeat(ma, len(mb)))
            vs.append(np.tile(mb, len(ma)))
    if not us:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(us), np.concatenate(vs)
