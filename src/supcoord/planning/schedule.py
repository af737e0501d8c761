"""From a sequence of single moves to a plan of simultaneous steps.

Two schedules of a valid single-move sequence: as-soon-as-possible in sequence order
(:func:`asap_schedule`, below) and the timeline schedule (:func:`timeline_schedule`,
its docstring has the argument), which lets a move overtake earlier moves of its
neighbours whose poses do not forbid it; :func:`plan_from_schedule` keeps the shorter.

As soon as possible:

Given a valid single-move sequence ``m_1 … m_K`` (each move allowed by the guarded model
from the configuration the moves before it produce), each move ``m_k`` of positioner
``p`` (joint ``j``) is given the earliest step ``s_k`` with

- ``s_k > s_i`` for every earlier move ``i`` of the same joint of ``p``;
- ``s_k ≥ s_i`` for every earlier move ``i`` of ``p``'s other joints and of every neighbour
  ``q`` of ``p`` (``problem.pairs``: every pair that could collide at all);
- if some other joint of ``p`` or some neighbour also moves at ``s_k``, the merged motion
  of step ``s_k`` is collision-free for every pair with ``p``
  (:func:`.descent.motion_free`, all moving joints together); otherwise
  ``s_k = s_min + 1``.

**Why the result is collision-free.**  Per positioner and per neighbour pair the order
of the moves is that of the sequence (steps never go backwards), so a pair in which only
one member moves during a step sees exactly the pair state and move it saw in the
sequence: allowed by the swept tables.  A step with ``p`` alone at ``s_min + 1`` is of
that kind (every earlier move of ``p`` and its neighbours is at ``≤ s_min``).  Every
step in which two members of a pair (or two joints of one positioner) move together was
checked when its last move was placed, with the full deltas of that step.  The final
configuration is the sequence's.  Greedy compaction (:func:`supcoord.problems.plan.compact_moves`) only
merges consecutive moves; this schedule lets independent work of distant windows run
in parallel, which is what a plan stitched from local windows needs.
"""

from __future__ import annotations

import bisect
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..geometry.collision import DEFAULT_TOL
from ..problems.plan import Move, Plan, checked_step, event_name, lower_bound
from ..problems.problem import Problem
from .descent import motion_free
from .guards import blocked_entries_of_pairs, conflict_graph, entry_lookup, is_blocked, pair_graph

__all__ = ["asap_schedule", "timeline_schedule", "plan_from_schedule", "SCHEDULES"]


def asap_schedule(problem: Problem, moves: Sequence[Move], tol: float = DEFAULT_TOL) -> list[np.ndarray]:
    """Configurations ``c_0 = start, …, c_T`` of the as-soon-as-possible schedule."""
    kin = problem.kinematics
    n, nj = problem.n, kin.n_joints
    nbrs = [[q for _, q, _ in row] for row in pair_graph(problem)]
    pair_of = {(p, q): (k, side) for p, row in enumerate(pair_graph(problem)) for k, q, side in row}
    move_index = {mv: m for m, mv in enumerate(kin.moves())}
    last_joint = np.full((n, nj), -1, dtype=np.int64)  # step of the last move of (p, j)
    last_any = np.full(n, -1, dtype=np.int64)
    cur = problem.start.astype(np.int64).copy()  # position after all moves placed so far
    deltas: dict[int, dict[int, np.ndarray]] = {}  # step -> {p: delta}
    for k, (p, joint, d) in enumerate(moves):
        nxt = checked_step(kin, cur[p], k, (p, joint, d))
        s_min = max(int(last_joint[p, joint]) + 1, int(last_any[p]), max((int(last_any[q]) for q in nbrs[p]), default=-1))
        s_min = max(s_min, 0)
        s = s_min
        at = deltas.get(s, {})
        busy = [q for q in nbrs[p] if q in at]
        if busy or p in at:
            dp = at.get(p, np.zeros(nj, dtype=np.int64)).copy()
            dp[joint] += d
            start_p = problem.kin(p).wrap(cur[p] - at[p]) if p in at else cur[p]  # a wrapping joint may have wrapped
            qs = nbrs[p]
            if p in at and problem.own_motion_blocked(p, start_p, dp, tol)[0]:
                s = s_min + 1  # several joints at once past a fixed obstacle
            elif qs:
                single = np.count_nonzero(dp) == 1
                standing = [q for q in qs if q not in at]
                if single and standing:  # against a standing neighbour one joint's turn is the exact swept table's entry
                    m = move_index[(int(np.nonzero(dp)[0][0]), int(dp[np.nonzero(dp)[0][0]]))]
                    i = kin.flat_position(start_p)
                    ks, sides = np.array([pair_of[(p, q)] for q in standing]).T
                    js = np.array([kin.flat_position(cur[q]) for q in standing])
                    if problem.tables().swept_bits(ks, sides, m, np.where(sides == 0, i, js),
                                                   np.where(sides == 0, js, i)).any():
                        s = s_min + 1
                moving = [q for q in qs if q in at or not single]
                if s == s_min:
                    for q in moving:
                        k_pair, side = pair_of[(p, q)]
                        start_q = problem.kin(q).wrap(cur[q] - at[q]) if q in at else cur[q]
                        if not motion_free(problem, k_pair, side, start_p, dp, start_q, at.get(q), tol):
                            s = s_min + 1
                            break
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
            c[p] = kin.wrap(c[p] + dp)
        out.append(c.copy())
    return out


SCHEDULES = ("timeline", "asap", "best")


def plan_from_schedule(problem: Problem, moves: Sequence[Move], stats: dict | None = None,
                       schedule: str = "best") -> Plan:
    """A ``complete`` plan of ``moves`` scheduled by :func:`timeline_schedule`,
    :func:`asap_schedule` or (``"best"``) the shorter of the two (``stats["schedule"]``
    says which)."""
    if schedule not in SCHEDULES:
        raise InputError(f"unknown schedule {schedule!r} (use {', '.join(SCHEDULES)})", value=schedule)
    stats = dict(stats or {})
    candidates = []
    if schedule in ("timeline", "best"):
        candidates.append(("timeline", timeline_schedule(problem, moves)))
    if schedule in ("asap", "best"):
        candidates.append(("asap", asap_schedule(problem, moves)))
    name, confs = min(candidates, key=lambda nc: len(nc[1]))
    stats["schedule"] = name
    if not np.array_equal(confs[-1], problem.target):
        raise InputError("the moves do not end at the target configuration", value=len(moves))
    events = [event_name(problem.kinematics, p, j, d) for p, j, d in moves]
    return Plan("complete", confs, len(confs) - 1, lower_bound(problem), events, "", stats)


class _Timeline:
    """Steps at which one positioner moves, its delta at each, and its positions:
    ``pos[0]`` = start, ``pos[i+1]`` = after the move at ``steps[i]``."""

    __slots__ = ("steps", "deltas", "pos", "last_joint")

    def __init__(self, start: np.ndarray, n_joints: int):
        self.steps: list[int] = []
        self.deltas: list[np.ndarray] = []
        self.pos: list[np.ndarray] = [start.copy()]
        self.last_joint = [-1] * n_joints

    def at(self, s: int) -> tuple[int, np.ndarray, np.ndarray | None]:
        """``(i, position before step s, delta at s or None)``."""
        i = bisect.bisect_left(self.steps, s)
        moving = i < len(self.steps) and self.steps[i] == s
        return i, self.pos[i], (self.deltas[i] if moving else None)


def timeline_schedule(problem: Problem, moves: Sequence[Move], tol: float = DEFAULT_TOL) -> list[np.ndarray]:
    """Configurations of the *timeline* schedule of a valid single-move sequence.

    Moves are placed in sequence order; move ``m_k`` of joint ``j`` of ``p``, from ``x``
    (``p``'s last placed position) to ``x'``, goes to the earliest step ``s`` with

    - ``s > `` the last step of joint ``j`` of ``p`` and ``s ≥`` the last step of ``p``
      (at that last step ``p``'s joints move together: ``x``, ``x'`` and the motion are
      that step's merged ones);
    - for every neighbour ``q`` (:attr:`Problem.pairs`), with ``q``'s placed timeline:
      the motion of ``p`` during ``s`` is free against ``q``'s position or motion during
      ``s`` (symmetrised swept table when one joint moves against a standing ``q``,
      :func:`.descent.motion_free` otherwise), and every move of
      ``q`` placed after ``s`` is free against ``p`` standing at ``x'``.

    **Why the result is collision-free.**  Invariant: all placed moves, executed on the
    timelines, are collision-free for every pair.  Placing ``m_k`` at ``s`` changes
    ``p``'s timeline only from step ``s`` on (``p`` has no placed move after ``s``): its
    motion during ``s`` and its pose ``x'`` during every later step are exactly what the
    two conditions check against each neighbour's timeline.  Per positioner the moves
    keep the sequence's order, so the last configuration is the sequence's.  Unlike
    :func:`asap_schedule`, a move need not wait for *every* earlier move of its
    neighbours — only for those whose poses actually forbid it — so the moves of a
    window can slide under the tail of an earlier, unrelated window.  The scan ends:
    at ``s`` beyond every neighbour's last placed step the neighbours stand where the
    sequence had them, where the move was allowed.
    """
    placer = _Placer(problem, tol)
    for k, move in enumerate(moves):
        placer.place(k, move)
    return placer.configurations()


class _Placer:
    """The timelines of the moves placed so far (:func:`timeline_schedule`)."""

    def __init__(self, problem: Problem, tol: float):
        kin = problem.kinematics
        self.problem, self.kin, self.tol = problem, kin, tol
        nj = kin.n_joints
        self.move_index = {mv: i for i, mv in enumerate(kin.moves())}
        self.side_of: dict[tuple[int, int], tuple[int, int]] = {}
        for p, row in enumerate(conflict_graph(problem)):
            for k, q, side in row:
                self.side_of[(p, q)] = (k, side)
        self.pair_nbrs = pair_graph(problem)
        self.lookup = entry_lookup(problem) if problem.tables().lazy else None
        self.tl = [_Timeline(problem.start[p].astype(np.int64), nj) for p in range(problem.n)]

    def single(self, d: np.ndarray) -> int | None:
        nz = np.nonzero(d)[0]
        return self.move_index[(int(nz[0]), int(d[nz[0]]))] if len(nz) == 1 else None

    def free(self, p: int, x: np.ndarray, dp: np.ndarray, q: int, k: int, side: int, y: np.ndarray,
             dq: np.ndarray | None) -> bool:
        """Is ``p`` moving ``x → x + dp`` free against ``q`` at ``y`` moving ``dq`` (None: standing)?"""
        mp = self.single(dp)
        if dq is None and mp is not None:
            ks = self.side_of.get((p, q))
            flat = self.kin.flat_position
            return ks is None or not is_blocked(self.problem, ks[0], ks[1], mp, flat(x), flat(y))
        return motion_free(self.problem, k, side, x, dp, y, dq, self.tol)

    def _prefetch(self, p: int, s: int, x: np.ndarray, dp: np.ndarray, x_end: np.ndarray) -> None:
        """Lazy tables: decide at once (:func:`.guards.blocked_entries_of_pairs`) every entry of a
        single move against a standing neighbour that :meth:`fits` may read."""
        flat, lookup = self.kin.flat_position, self.lookup
        cells = []
        mp = self.single(dp)
        for k, q, side in self.pair_nbrs[p]:
            t = self.tl[q]
            i, y, dq = t.at(s)
            ks = self.side_of.get((p, q))
            if dq is None and mp is not None and ks is not None:
                cells.append((ks[0], ks[1], mp, flat(x), flat(y)))
            ks = self.side_of.get((q, p))
            if ks is None:
                continue
            end = flat(x_end)
            for idx in range(i + (dq is not None), len(t.steps)):
                mq = self.single(t.deltas[idx])
                if mq is not None:
                    cells.append((ks[0], ks[1], mq, flat(t.pos[idx]), end))
        cells = [c for c in cells if lookup(*c) is None]
        if cells:
            blocked_entries_of_pairs(self.problem, *np.array(cells).T)

    def fits(self, p: int, s: int, x: np.ndarray, dp: np.ndarray, x_end: np.ndarray) -> bool:
        """Both conditions of :func:`timeline_schedule` for ``p`` moving ``x → x_end`` (by
        ``dp``) during step ``s``."""
        if np.count_nonzero(dp) > 1 and self.problem.own_motion_blocked(p, x, dp, self.tol)[0]:
            return False
        if self.lookup is not None:
            self._prefetch(p, s, x, dp, x_end)
        for k, q, side in self.pair_nbrs[p]:
            t = self.tl[q]
            i, y, dq = t.at(s)
            if not self.free(p, x, dp, q, k, side, y, dq):
                return False
            for idx in range(i + (dq is not None), len(t.steps)):  # q's later moves vs p at x'
                if not self.free(q, t.pos[idx], t.deltas[idx], p, k, 1 - side, x_end, None):
                    return False
        return True

    def place(self, k_move: int, move: Move) -> None:
        """Put move number ``k_move`` into its positioner's last step if it fits there,
        else at the earliest step after it that fits."""
        p, joint, d = move
        kin, t = self.kin, self.tl[p]
        checked_step(kin, t.pos[-1], k_move, move)
        e = np.zeros(kin.n_joints, dtype=np.int64)
        e[joint] = d
        last = t.steps[-1] if t.steps else -1
        if last >= 0 and t.last_joint[joint] < last:  # join p's last step
            x, dp = t.pos[-2], t.deltas[-1] + e
            x_end = self.kin.wrap(x + dp)
            if self.fits(p, last, x, dp, x_end):
                t.deltas[-1] = dp
                t.pos[-1] = x_end
                t.last_joint[joint] = last
                return
        s = last + 1
        x = t.pos[-1]
        x_end = self.kin.wrap(x + e)
        while not self.fits(p, s, x, e, x_end):
            s += 1
        t.steps.append(s)
        t.deltas.append(e)
        t.pos.append(x_end)
        t.last_joint[joint] = s

    def configurations(self) -> list[np.ndarray]:
        """``c_0 … c_T`` of the placed timelines."""
        n, nj = self.problem.n, self.kin.n_joints
        horizon = max((t.steps[-1] for t in self.tl if t.steps), default=-1) + 1
        return [np.array([t.at(s)[1] for t in self.tl], dtype=np.int64).reshape(n, nj) for s in range(horizon + 1)]
