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
from .descent import MotionChecker
from .guards import blocked_entries, blocked_entry, blocked_lookup, conflict_graph, pair_graph

__all__ = ["asap_schedule", "timeline_schedule", "plan_from_schedule", "SCHEDULES"]


def asap_schedule(problem: Problem, moves: Sequence[Move], tol: float = DEFAULT_TOL) -> list[np.ndarray]:
    """Configurations ``c_0 = start, …, c_T`` of the as-soon-as-possible schedule.

    Moves are placed in sequence order; move ``m_k`` of joint ``j`` of ``p`` goes to the
    earliest step ``s_min`` after the last step of joint ``j`` of ``p`` and no earlier than
    the last step of ``p`` and of each of its neighbours, if it is free there together with
    the moves already at ``s_min`` (:meth:`_Asap.fits`), else to ``s_min + 1``.
    """
    asap = _Asap(problem, tol)
    for k, move in enumerate(moves):
        asap.place(k, move)
    return asap.configurations()


class _Asap:
    """The steps of the moves placed so far by :func:`asap_schedule`."""

    def __init__(self, problem: Problem, tol: float):
        kin = problem.kinematics
        self.problem, self.kin, self.tol = problem, kin, tol
        n, nj = problem.n, kin.n_joints
        self.nbrs = [[q for _, q, _ in row] for row in pair_graph(problem)]
        self.pair_of = {(p, q): (k, side) for p, row in enumerate(pair_graph(problem)) for k, q, side in row}
        self.move_index = {mv: m for m, mv in enumerate(kin.moves())}
        self.last_joint = np.full((n, nj), -1, dtype=np.int64)  # step of the last move of (p, j)
        self.last_any = np.full(n, -1, dtype=np.int64)
        self.cur = problem.start.astype(np.int64).copy()  # position after all moves placed so far
        self.deltas: dict[int, dict[int, np.ndarray]] = {}  # step -> {p: delta}
        self.strides = [int(v) for v in kin._strides]
        self.motions = MotionChecker(problem, tol)

    def place(self, k: int, move: Move) -> None:
        """Put move number ``k`` at the earliest step it may take (:func:`asap_schedule`)."""
        p, joint, d = move
        nxt = checked_step(self.kin, self.cur[p], k, (p, joint, d))
        s_min = max(int(self.last_joint[p, joint]) + 1, int(self.last_any[p]),
                    max((int(self.last_any[q]) for q in self.nbrs[p]), default=-1))
        s_min = max(s_min, 0)
        s = s_min if self.fits(p, joint, d, s_min) else s_min + 1
        step_map = self.deltas.setdefault(s, {})
        step_map.setdefault(p, np.zeros(self.kin.n_joints, dtype=np.int64))[joint] += d
        self.last_joint[p, joint] = s
        self.last_any[p] = max(self.last_any[p], s)
        self.cur[p] = nxt

    def fits(self, p: int, joint: int, d: int, s: int) -> bool:
        """May ``p`` turn ``joint`` by ``d`` during step ``s``, merged with its own move there and
        beside its neighbours' moves there?"""
        problem, at, qs = self.problem, self.deltas.get(s, {}), self.nbrs[p]
        if p not in at and not any(q in at for q in qs):
            return True
        nj = self.kin.n_joints
        dp = at.get(p, np.zeros(nj, dtype=np.int64)).copy()
        dp[joint] += d
        start_p = problem.kin(p).wrap(self.cur[p] - at[p]) if p in at else self.cur[p]  # a wrapping joint may have wrapped
        if p in at and problem.own_motion_blocked(p, start_p, dp, self.tol)[0]:
            return False  # several joints at once past a fixed obstacle
        if not qs:
            return bool(at[p][joint] == 0)
        single = np.count_nonzero(dp) == 1
        standing = [q for q in qs if q not in at]
        if single and standing and self._turn_hits(p, dp, start_p, standing):
            return False
        for q in (q for q in qs if q in at or not single):
            k_pair, side = self.pair_of[(p, q)]
            start_q = problem.kin(q).wrap(self.cur[q] - at[q]) if q in at else self.cur[q]
            if not self.motions.free(k_pair, side, start_p, dp, start_q, at.get(q)):
                return False
        return True

    def _turn_hits(self, p: int, dp: np.ndarray, start_p: np.ndarray, standing: list[int]) -> bool:
        """Does ``p`` turning its one joint by ``dp`` from ``start_p`` hit a neighbour of
        ``standing``?  Against a standing neighbour one joint's turn is the exact swept
        table's entry (:meth:`CollisionTables.swept_entries`; eager tables: read one bit at a
        time, on Python ints, until one collides)."""
        d = dp.tolist()
        joint = next(j for j, v in enumerate(d) if v)
        m = self.move_index[(joint, d[joint])]
        i = self.flat(start_p)
        tables = self.problem.tables()
        if not tables.lazy:
            for q in standing:
                k, side = self.pair_of[(p, q)]
                j = self.flat(self.cur[q])
                if tables.swept_entry(k, side, m, i, j) if side == 0 else tables.swept_entry(k, side, m, j, i):
                    return True
            return False
        ks, sides = np.array([self.pair_of[(p, q)] for q in standing]).T
        js = np.array([self.flat(self.cur[q]) for q in standing])
        return bool(tables.swept_entries(ks, sides, m, np.where(sides == 0, i, js), np.where(sides == 0, js, i)).any())

    def flat(self, q: np.ndarray) -> int:
        """:meth:`Kinematics.flat_position` of ``q`` on Python ints."""
        return sum(v * st for v, st in zip(q.tolist(), self.strides))

    def configurations(self) -> list[np.ndarray]:
        """``c_0 … c_T`` of the placed moves."""
        problem, kin = self.problem, self.kin
        out = [problem.start.copy()]
        c = problem.start.astype(np.int64).copy()
        for s in range(max(self.deltas, default=-1) + 1):
            for p, dp in self.deltas.get(s, {}).items():
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
        self.lookup = blocked_lookup(problem) if problem.tables().lazy else None
        self.tl = [_Timeline(problem.start[p].astype(np.int64), nj) for p in range(problem.n)]
        self._single: dict[tuple[int, ...], int | None] = {}
        self.strides = [int(v) for v in kin._strides]
        self.motions = MotionChecker(problem, tol)

    def single(self, d: np.ndarray) -> int | None:
        """The move index of the delta ``d`` if it turns one joint, else None (memoised by delta)."""
        key = tuple(d.tolist())
        out = self._single.get(key, -1)
        if out == -1:
            nz = [j for j, v in enumerate(key) if v]
            out = self._single[key] = self.move_index[(nz[0], key[nz[0]])] if len(nz) == 1 else None
        return out

    def flat(self, q: np.ndarray) -> int:
        """:meth:`Kinematics.flat_position` of ``q`` on Python ints."""
        return sum(v * st for v, st in zip(q.tolist(), self.strides))

    def free(self, p: int, x: np.ndarray, dp: np.ndarray, q: int, k: int, side: int, y: np.ndarray,
             dq: np.ndarray | None) -> bool:
        """Is ``p`` moving ``x → x + dp`` free against ``q`` at ``y`` moving ``dq`` (None: standing)?"""
        mp = self.single(dp)
        if dq is None and mp is not None:
            ks = self.side_of.get((p, q))
            return ks is None or not blocked_entry(self.problem, ks[0], ks[1], mp, self.flat(x), self.flat(y))
        return self.motions.free(k, side, x, dp, y, dq)

    def _prefetch(self, p: int, s: int, x: np.ndarray, dp: np.ndarray, x_end: np.ndarray) -> None:
        """Lazy tables: decide at once (:func:`.guards.blocked_entries`) every entry of a
        single move against a standing neighbour that :meth:`fits` may read."""
        flat, lookup = self.flat, self.lookup
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
            blocked_entries(self.problem, *np.array(cells).T)

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
