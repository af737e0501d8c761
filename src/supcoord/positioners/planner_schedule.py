"""From a sequence of single moves to a plan of simultaneous steps (as-soon-as-possible).

Given a valid single-move sequence ``m_1 … m_K`` (each move allowed by the guarded model
from the configuration the moves before it produce), each move ``m_k`` of positioner
``p`` (joint ``j``) is given the earliest step ``s_k`` with

- ``s_k > s_i`` for every earlier move ``i`` of the same joint of ``p``;
- ``s_k ≥ s_i`` for every earlier move ``i`` of ``p``'s other joints and of every neighbour
  ``q`` of ``p`` (``problem.pairs``: every pair that could collide at all);
- if some other joint of ``p`` or some neighbour also moves at ``s_k``, the merged motion
  of step ``s_k`` is collision-free for every pair with ``p``
  (:func:`~.collision.motion_collides`, all moving joints together); otherwise
  ``s_k = s_min + 1``.

**Why the result is collision-free.**  Per positioner and per neighbour pair the order
of the moves is that of the sequence (steps never go backwards), so a pair in which only
one member moves during a step sees exactly the pair state and move it saw in the
sequence: allowed by the swept tables.  A step with ``p`` alone at ``s_min + 1`` is of
that kind (every earlier move of ``p`` and its neighbours is at ``≤ s_min``).  Every
step in which two members of a pair (or two joints of one positioner) move together was
checked when its last move was placed, with the full deltas of that step.  The final
configuration is the sequence's.  Greedy compaction (:func:`.plan.compact_moves`) only
merges consecutive moves; this schedule lets independent work of distant windows run
in parallel, which is what a plan stitched from local windows needs.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..errors import InputError
from .collision import DEFAULT_TOL, motion_collides
from .plan import Move, Plan, event_name, lower_bound
from .problem import Problem

__all__ = ["asap_schedule", "plan_from_schedule"]


def asap_schedule(problem: Problem, moves: Sequence[Move], tol: float = DEFAULT_TOL) -> list[np.ndarray]:
    """Configurations ``c_0 = start, …, c_T`` of the as-soon-as-possible schedule."""
    kin = problem.kinematics
    n, nj = problem.n, kin.n_joints
    nbrs: list[list[int]] = [[] for _ in range(n)]
    for a, b in problem.pairs:
        nbrs[int(a)].append(int(b))
        nbrs[int(b)].append(int(a))
    last_joint = np.full((n, nj), -1, dtype=np.int64)  # step of the last move of (p, j)
    last_any = np.full(n, -1, dtype=np.int64)
    cur = problem.start.astype(np.int64).copy()  # position after all moves placed so far
    deltas: dict[int, dict[int, np.ndarray]] = {}  # step -> {p: delta}
    bsum = problem.buffers
    for k, (p, joint, d) in enumerate(moves):
        nxt = kin.step(cur[p], joint, d)
        if nxt is None:
            raise InputError(f"move {k} ({event_name(kin, p, joint, d)}) drives positioner {p} past a hard stop",
                             value=(p, joint, d))
        s_min = max(int(last_joint[p, joint]) + 1, int(last_any[p]), max((int(last_any[q]) for q in nbrs[p]), default=-1))
        s_min = max(s_min, 0)
        s = s_min
        at = deltas.get(s, {})
        busy = [q for q in nbrs[p] if q in at]
        if busy or p in at:
            dp = at.get(p, np.zeros(nj, dtype=np.int64)).copy()
            dp[joint] += d
            start_p = cur[p] - at[p] if p in at else cur[p]
            qs = nbrs[p]
            if qs:
                qa = np.array(qs)
                dq = np.array([at.get(q, np.zeros(nj, dtype=np.int64)) for q in qs])
                start_q = np.array([cur[q] - at[q] if q in at else cur[q] for q in qs])
                hit = motion_collides(kin, problem.bases[p], start_p, dp, kin, problem.bases[qa], start_q, dq,
                                      bsum[p] + bsum[qa], tol)
                if hit.any():
                    s = s_min + 1
            else:
                s = s_min if p not in at or at[p][joint] == 0 else s_min + 1
        step_map = deltas.setdefault(s, {})
        step_map.setdefault(p, np.zeros(nj, dtype=np.int64))[joint] += d
        last_joint[p, joint] = s
        last_any[p] = max(last_any[p], s)
        cur[p] = nxt
    out = [problem.start.copy()]
    c = problem.start.astype(np.int64).copy()
    for s in range(max(deltas, default=-1) + 1):
        for p, dp in deltas.get(s, {}).items():
            c[p] = c[p] + dp
            for j, jt in enumerate(kin.joints):
                if jt.wraps:
                    c[p, j] %= jt.steps
        out.append(c.copy())
    return out


def plan_from_schedule(problem: Problem, moves: Sequence[Move], stats: dict | None = None) -> Plan:
    """A ``complete`` plan of the as-soon-as-possible schedule of ``moves``."""
    confs = asap_schedule(problem, moves)
    if not np.array_equal(confs[-1], problem.target):
        raise InputError("the moves do not end at the target configuration", value=len(moves))
    events = [event_name(problem.kinematics, p, j, d) for p, j, d in moves]
    return Plan("complete", confs, len(confs) - 1, lower_bound(problem), events, "", dict(stats or {}))
