"""Explicit twins of the planner's *encoding*: breadth-first search over the planner's own guards.

**Not a geometric oracle.**  Every function here reads the planner's guards
(:func:`supcoord.planning.guards.blocked_table`, :func:`~supcoord.planning.guards.conflict_graph`,
the collision tables behind them, :func:`supcoord.geometry.collision.motion_collides`), so
"symbolic = BFS" checks that the BDDs encode those guards — not that the guards are
right.  Geometric verdicts are checked against :mod:`supcoord.testing.oracle`, which
shares no code with the planner.

- :func:`bfs_plan_naive` — the single-move (interleaving) semantics of ``docs/formats.md``
  on the same guarded model as :mod:`supcoord.planning.model`::

      succ(c) = {c[p ↦ step_m(c_p)] : p ∈ P, m a move of p, step defined,
                 ∀ (p, q) conflicting. ¬B_{p,m}(c_p, c_q)}

  returns the BFS distance (the length of a shortest single-move plan, which the
  symbolic ``rank(q0)`` must equal) and one shortest move sequence, or ``None`` when the
  target is not reachable (the problem is infeasible).
- :func:`optimal_makespan_naive` — the simultaneous semantics: in one step every joint
  of every positioner moves ``−1``, ``0`` or ``+1``, and the step is allowed when every
  neighbour pair's simultaneous motion is free (:func:`~supcoord.geometry.collision.motion_collides`);
  BFS gives the optimal makespan, the yardstick for the planner's scheduled plans.

- :func:`reachable_naive`, :func:`blockers_naive` — a window's reachable set (members
  move, the others frozen or removed) and its blockers, the twins of
  :func:`supcoord.planning.search.search`'s closed side and :func:`supcoord.planning.search.blockers`.

All enumerate up to ``∏ |Q_p|`` configurations: for 2–4 positioners only.

References
----------
- E. F. Moore, The shortest path through a maze, 1959 (breadth-first search).
"""

from __future__ import annotations

import itertools
from collections import deque
from typing import Callable

import numpy as np

from ..errors import InputError
from ..geometry.collision import motion_collides
from ..planning.guards import blocked_table, conflict_graph
from ..problems.plan import Move
from ..problems.problem import Problem

__all__ = ["MAX_NAIVE_STATES", "bfs_plan_naive", "blockers_naive", "optimal_makespan_naive", "reachable_naive"]

#: refuse explicit searches over more configurations than this
MAX_NAIVE_STATES = 5_000_000


def _check_size(problem: Problem) -> None:
    total = problem.kinematics.n_positions ** problem.n
    if total > MAX_NAIVE_STATES:
        raise InputError(f"explicit search over {total} configurations exceeds {MAX_NAIVE_STATES}", value=total)


def bfs_plan_naive(problem: Problem, start: np.ndarray | None = None) -> tuple[int, list[Move]] | None:
    """``(distance, moves)`` of a shortest single-move plan start → target, or ``None``."""
    _check_size(problem)
    kin = problem.kinematics
    adj = conflict_graph(problem)
    pos = kin.all_positions()
    moves = kin.moves()
    # successor table of one positioner: nxt[m, i] (−1 past a hard stop)
    nxt = np.full((len(moves), len(pos)), -1, dtype=np.int64)
    for m, (joint, delta) in enumerate(moves):
        for i in range(len(pos)):
            s = kin.step(pos[i], joint, delta)
            if s is not None:
                nxt[m, i] = int(kin.flat_index(s))
    blocked = [[(q, blocked_table(problem, k, side)) for k, q, side in adj[p]] for p in range(problem.n)]
    s0 = tuple(int(i) for i in kin.flat_index(problem.start if start is None else start))
    goal = tuple(int(i) for i in kin.flat_index(problem.target))
    parent: dict[tuple, tuple | None] = {s0: None}
    queue = deque([s0])
    while queue:
        s = queue.popleft()
        if s == goal:
            break
        for p in range(problem.n):
            for m in range(len(moves)):
                j = nxt[m, s[p]]
                if j < 0 or any(b[m, s[p], s[q]] for q, b in blocked[p]):
                    continue
                t = s[:p] + (int(j),) + s[p + 1:]
                if t not in parent:
                    parent[t] = (s, (p, moves[m][0], moves[m][1]))
                    queue.append(t)
    if goal not in parent:
        return None
    out: list[Move] = []
    s = goal
    while parent[s] is not None:
        s, mv = parent[s]  # type: ignore[misc]
        out.append(mv)
    return len(out), out[::-1]


def _step_options(problem: Problem) -> list[np.ndarray]:
    """Per-step joint deltas of one positioner: ``{−1, 0, +1}^J``, standing first."""
    nj = problem.kinematics.n_joints
    opts = [np.array(d, dtype=np.int64) for d in itertools.product((0, 1, -1), repeat=nj)]
    return opts


def _simultaneous_full(problem: Problem, k: int, options: list[np.ndarray], nxt: np.ndarray) -> np.ndarray:
    """``S[u, v, i, j]``: pair ``k``'s members doing the deltas ``options[u]`` / ``options[v]``
    from positions ``i`` / ``j`` at once collide, or leave the joint ranges (True)."""
    kin = problem.kinematics
    a, b = (int(x) for x in problem.pairs[k])
    pos = kin.all_positions()
    n = len(pos)
    bsum = problem.buffers[a] + problem.buffers[b]
    ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    ii, jj = ii.ravel(), jj.ravel()
    out = np.ones((len(options), len(options), n, n), dtype=bool)
    ok = nxt >= 0  # [u, i]: the deltas stay inside the hard stops

    def allowed(r: int) -> np.ndarray:  # ... and the robot's own constraints (obstacles, held)
        if r not in problem.unary():
            return ok
        return ok & ~np.array([problem.own_motion_blocked(r, pos, d) for d in options])

    ok_a, ok_b = allowed(a), allowed(b)
    for u, du in enumerate(options):
        for v, dv in enumerate(options):
            sel = ok_a[u][ii] & ok_b[v][jj]
            hit = motion_collides(problem.kin(a), problem.bases[a], pos[ii[sel]], du, problem.kin(b), problem.bases[b],
                                  pos[jj[sel]], dv,
                                  bsum)
            block = np.ones(n * n, dtype=bool)
            block[np.nonzero(sel)[0]] = hit
            out[u, v] = block.reshape(n, n)
    return out


def optimal_makespan_naive(problem: Problem) -> int | None:
    """Fewest simultaneous steps start → target, or ``None`` if unreachable.

    A step moves every joint of every positioner by −1, 0 or +1 at once (linearly, as
    the validator interpolates); it is allowed when every neighbour pair's simultaneous
    motion is free (:func:`~supcoord.geometry.collision.motion_collides`, computed here table by table).
    This is the validator's semantics, wider than the single-move model (two arms may
    pass in tandem), so its optimum is a lower bound for any plan of the planner.
    Breadth-first search over ``∏ |Q_p|`` configurations and ``3^{J·N}`` steps: for
    2–4 rotary or 2 alpha-beta positioners."""
    kin = problem.kinematics
    _check_size(problem)
    options = _step_options(problem)
    if len(options) ** problem.n > 10_000:
        raise InputError(f"{len(options) ** problem.n} simultaneous steps per configuration is too many for "
                         "the explicit search", value=problem.n)
    pos = kin.all_positions()
    nxt = np.full((len(options), len(pos)), -1, dtype=np.int64)
    for u, d in enumerate(options):
        for i in range(len(pos)):
            q = kin.wrap(pos[i] + d)
            if np.all(kin.in_range(q)):
                nxt[u, i] = int(kin.flat_index(q))
    pairs = [(int(a), int(b), _simultaneous_full(problem, k, options, nxt)) for k, (a, b) in enumerate(problem.pairs)]
    s0 = tuple(int(v) for v in kin.flat_index(problem.start))
    goal = tuple(int(v) for v in kin.flat_index(problem.target))
    combos = [c for c in itertools.product(range(len(options)), repeat=problem.n) if any(c)]
    dist = {s0: 0}
    queue = deque([s0])
    while queue:
        s = queue.popleft()
        if s == goal:
            return dist[s]
        for c in combos:
            if any(nxt[c[p], s[p]] < 0 for p in range(problem.n)):
                continue
            if any(S[c[a], c[b], s[a], s[b]] for a, b, S in pairs):
                continue
            t = tuple(int(nxt[c[p], s[p]]) for p in range(problem.n))
            if t not in dist:
                dist[t] = dist[s] + 1
                queue.append(t)
    return None


def reachable_naive(problem: Problem, members: list[int], c: np.ndarray,
                    frozen: bool = True, keep: Callable[[tuple[int, ...]], bool] | None = None) -> set[tuple[int, ...]]:
    """Configurations of ``members`` (flat positions, in ``members`` order) reachable from
    ``c`` by single moves of the members, the others frozen at ``c`` (``frozen``) or
    removed — the explicit twin of a window's ``Reach(q0)``; with ``keep``, only through
    configurations it accepts (the twin of a restricted system)."""
    kin = problem.kinematics
    total = kin.n_positions ** len(members)
    if total > MAX_NAIVE_STATES:
        raise InputError(f"explicit search over {total} configurations exceeds {MAX_NAIVE_STATES}", value=total)
    adj = conflict_graph(problem)
    moves = kin.moves()
    pos = kin.all_positions()
    where = {p: i for i, p in enumerate(members)}
    flat_c = kin.flat_index(c)
    s0 = tuple(int(flat_c[p]) for p in members)
    seen = {s0}
    queue = deque([s0])
    while queue:
        s = queue.popleft()
        for a, p in enumerate(members):
            for m, (joint, delta) in enumerate(moves):
                nxt = kin.step(pos[s[a]], joint, delta)
                if nxt is None:
                    continue
                ok = True
                for k, q, side in adj[p]:
                    if q in where:
                        other = s[where[q]]
                    elif frozen:
                        other = int(flat_c[q])
                    else:
                        continue
                    if blocked_table(problem, k, side)[m, s[a], other]:
                        ok = False
                        break
                if ok:
                    t = s[:a] + (int(kin.flat_index(nxt)),) + s[a + 1:]
                    if t not in seen and (keep is None or keep(t)):
                        seen.add(t)
                        queue.append(t)
    return seen


def blockers_naive(problem: Problem, members: list[int], c: np.ndarray) -> list[int]:
    """Explicit twin of :func:`supcoord.planning.search.blockers` on ``Reach(c)`` of the window:
    the outsiders whose frozen position forbids a move every member allows at a
    reachable configuration."""
    kin = problem.kinematics
    adj = conflict_graph(problem)
    moves = kin.moves()
    pos = kin.all_positions()
    where = {p: i for i, p in enumerate(members)}
    flat_c = kin.flat_index(c)
    found: set[int] = set()
    for s in reachable_naive(problem, members, c):
        for a, p in enumerate(members):
            for m, (joint, delta) in enumerate(moves):
                if kin.step(pos[s[a]], joint, delta) is None:
                    continue
                inside_ok = all(not blocked_table(problem, k, side)[m, s[a], s[where[q]]]
                                for k, q, side in adj[p] if q in where)
                if not inside_ok:
                    continue
                for k, q, side in adj[p]:
                    if q not in where and blocked_table(problem, k, side)[m, s[a], int(flat_c[q])]:
                        found.add(q)
    return sorted(found)
