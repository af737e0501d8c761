"""Greedy simultaneous descent: every unfinished positioner steps towards its target at once.

One *descent step* from a configuration ``c`` chooses, positioner by positioner in
priority order (smaller number first, then index), a set ``M_p`` of single-joint moves
towards ``p``'s target (every joint that is off target, one step the short way round;
if that set is refused, each joint alone; at half a turn both ways are tried) and
keeps the first that is *compatible* with the choices made so far:

1. **serialisable in any order** — for every neighbour pair ``(p, q)`` that can block
   a move (:func:`.coordination.conflict_graph`), every move ``μ = (p, m) ∈ M_p`` is
   allowed by the symmetrised swept table ``B`` from every pose ``p`` can have when
   ``μ`` starts (its other moves of the step done or not) against every pose of ``q``
   (any subset of ``M_q`` done), and the same with ``p`` and ``q`` exchanged::

       ∀ μ ∈ M_p, A ⊆ M_p \\ {μ}, A' ⊆ M_q.   ¬B_{p,m}(c_p + A, c_q + A')

   Guards are conjunctions over pairs, so then *every* ordering of the step's moves is
   a valid single-move sequence of the guarded model (:mod:`.coordination`);
2. **collision-free when merged** — for every neighbour pair (:attr:`Problem.pairs`)
   in which both move, or one moves two joints, the simultaneous motion
   ``c + t·Δ`` is free (:meth:`CollisionTables.simultaneous` for one joint each,
   :func:`.collision.motion_collides` otherwise).

Steps repeat until every positioner is at target or a step chooses nothing (a stall).
Each step strictly lowers ``Σ_p Σ_j d_j(c_p, target_p)``, so the descent ends.

**Why it keeps the planner exact.**  By (1) the descent is a sequence of single moves
of the guarded model, so the configuration ``c*`` it ends in is reachable from the
start in the single-move graph; the graph is undirected, hence the target is
reachable from ``c*`` iff from the start, and the exact symbolic windows of
:mod:`.planner_local` may continue from ``c*`` without changing any verdict.  By (2)
and the swept tables, each step is collision-free as executed simultaneously.  The
descent never answers "infeasible"; it only shortens the exact search and the plan.

References
----------
- C. Sayres et al., kaiju: SDSS-V robots move greedily towards target while the
  motion is free (here: with the serialisability condition that keeps exactness).
- E. F. Moore 1959 / the single-move model of ``formats.md``.
"""

from __future__ import annotations

import itertools
from typing import Callable, Sequence

import numpy as np

from .collision import DEFAULT_TOL, motion_collides
from .coordination import blocked_table, conflict_graph
from .plan import Move
from .problem import Problem

__all__ = ["descent", "descent_step", "wanted_moves"]


def wanted_moves(problem: Problem, c: np.ndarray, p: int) -> list[list[tuple[int, int]]]:
    """Candidate move sets of ``p`` towards its target, most ambitious first."""
    kin = problem.kinematics
    per_joint: list[list[tuple[int, int]]] = []
    for j, jt in enumerate(kin.joints):
        a, b = int(c[p, j]), int(problem.target[p, j])
        if a == b:
            continue
        if jt.wraps:
            fwd = (b - a) % jt.steps
            if 2 * fwd == jt.steps:
                per_joint.append([(j, +1), (j, -1)])
            else:
                per_joint.append([(j, +1 if 2 * fwd < jt.steps else -1)])
        else:
            per_joint.append([(j, +1 if b > a else -1)])
    out: list[list[tuple[int, int]]] = []
    if len(per_joint) > 1:
        out.extend([list(combo) for combo in itertools.product(*per_joint)])
    for options in per_joint:
        out.extend([[mv] for mv in options])
    return out


class _Tables:
    """Per-problem lookups: moves, strides, conflict adjacency, pair adjacency."""

    def __init__(self, problem: Problem):
        kin = problem.kinematics
        self.problem = problem
        self.kin = kin
        self.moves = kin.moves()
        self.move_index = {mv: i for i, mv in enumerate(self.moves)}
        self.shape = np.array(kin.shape)
        self.strides = np.array([int(np.prod(kin.shape[j + 1:])) for j in range(kin.n_joints)])
        self.adj = conflict_graph(problem)
        self.pair_adj: list[list[tuple[int, int, int]]] = [[] for _ in range(problem.n)]
        for k, (a, b) in enumerate(problem.pairs):
            self.pair_adj[int(a)].append((k, int(b), 0))
            self.pair_adj[int(b)].append((k, int(a), 1))
        self.tables = problem.tables()

    def pose(self, q: np.ndarray, ms: Sequence[tuple[int, int]]) -> np.ndarray:
        out = q.copy()
        for j, d in ms:
            out[j] += d
            if self.kin.joints[j].wraps:
                out[j] %= self.shape[j]
        return out

    def flat(self, q: np.ndarray) -> int:
        return int(np.dot(q, self.strides))


def _subsets(ms: Sequence[tuple[int, int]]) -> list[list[tuple[int, int]]]:
    return [list(s) for r in range(len(ms) + 1) for s in itertools.combinations(ms, r)]


def _serialisable(T: _Tables, k: int, side: int, cp: np.ndarray, mp: list, cq: np.ndarray, mq: list) -> bool:
    """Condition (1) for the moves ``mp`` of the pair member ``side`` against ``mq``."""
    blocked = blocked_table(T.problem, k, side)
    q_poses = [T.flat(T.pose(cq, s)) for s in _subsets(mq)]
    for mv in mp:
        m = T.move_index[mv]
        others = [x for x in mp if x != mv]
        for s in _subsets(others):
            i = T.flat(T.pose(cp, s))
            if any(blocked[m, i, j] for j in q_poses):
                return False
    return True


def _compatible(T: _Tables, c: np.ndarray, chosen: dict[int, list], p: int, mp: list, tol: float) -> bool:
    problem = T.problem
    for k, q, side in T.adj[p]:  # (1): both orders, every subset
        mq = chosen.get(q, [])
        if not _serialisable(T, k, side, c[p], mp, c[q], mq):
            return False
        if mq and not _serialisable(T, k, 1 - side, c[q], mq, c[p], mp):
            return False
    for k, q, side in T.pair_adj[p]:  # (2): merged motion of the pair
        mq = chosen.get(q, [])
        if not mq and len(mp) < 2:
            continue  # one joint against a standing neighbour: the swept table of (1)
        if len(mp) == 1 and len(mq) == 1:
            sim = T.tables.simultaneous(k)  # [u_a, v_b, i_a, j_b]
            u, v = 1 + T.move_index[mp[0]], 1 + T.move_index[mq[0]]
            i, j = T.flat(c[p]), T.flat(c[q])
            hit = sim[u, v, i, j] if side == 0 else sim[v, u, j, i]
        else:
            dp, dq = np.zeros(T.kin.n_joints), np.zeros(T.kin.n_joints)
            for jj, d in mp:
                dp[jj] = d
            for jj, d in mq:
                dq[jj] = d
            bsum = problem.buffers[p] + problem.buffers[q]
            hit = bool(motion_collides(T.kin, problem.bases[p], c[p], dp, T.kin, problem.bases[q], c[q], dq,
                                       bsum, tol))
        if hit:
            return False
    return True


def descent_step(problem: Problem, c: np.ndarray, T: _Tables | None = None,
                 tol: float = DEFAULT_TOL) -> list[Move]:
    """The moves of one descent step from ``c`` (empty: a stall), in priority order."""
    T = T or _Tables(problem)
    todo = [p for p in range(problem.n) if not np.array_equal(c[p], problem.target[p])]
    todo.sort(key=lambda p: (problem.priority[p], p))
    chosen: dict[int, list] = {}
    for p in todo:
        for mp in wanted_moves(problem, c, p):
            if _compatible(T, c, chosen, p, mp, tol):
                chosen[p] = mp
                break
    return [(p, j, d) for p in todo if p in chosen for j, d in chosen[p]]


def descent(problem: Problem, c: np.ndarray, max_steps: int | None = None,
            check: Callable[..., None] | None = None) -> tuple[list[list[Move]], np.ndarray]:
    """Descent steps from ``c`` until all are at target or a stall: ``(steps, end)``.
    ``check(stage, **info)`` is called before every step (budgets, progress)."""
    T = _Tables(problem)
    steps: list[list[Move]] = []
    c = c.copy()
    while max_steps is None or len(steps) < max_steps:
        if check is not None:
            check("descent", iteration=len(steps))
        step = descent_step(problem, c, T)
        if not step:
            break
        for p, j, d in step:
            c[p] = T.pose(c[p], [(j, d)])
        steps.append(step)
    return steps, c
