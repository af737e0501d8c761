"""The scalable route: exact symbolic solves on windows, certificates both ways.

Write ``C(S, c)`` for the guarded model of :mod:`.coordination` with members ``S`` moving
from the configuration ``c`` and the others frozen at ``c``, and ``R(S)`` for the
*relaxed* subproblem: only ``S``, the others removed, from ``start|_S`` to ``target|_S``.

Algorithm (``c := start``)::

    for each conflict component K, for p ∈ K in variable order with c_p ≠ target_p:
        for S in windows(p) = the 1, 4, 7, 13, 19, … members of K nearest to p, …, K:
            if C(S, c) reaches D = {p and the members already at target, at target}:
                                      append its witness moves, c := their end; next p
            if S = K:                 infeasible, certificate K
            if R(S) is infeasible:    infeasible, certificate S

Why it is exact (sound and complete, within the budgets):

1. **Components are independent.**  Positioners of different conflict components share no
   guard, so a plan of the whole is an interleaving of plans of the components and the
   whole is feasible iff every component is.
2. **Window moves are moves of the whole.**  A move allowed in ``C(S, c)`` is guarded by
   every neighbour of the mover (inside ``S`` by the pair guard, outside by the unary guard
   at its actual, frozen position), so the witness is a valid move sequence of the whole
   problem from ``c``.  Each success puts ``p`` at target, keeps the members that were at
   target there and leaves the rest as it was, so the number of positioners at target
   grows strictly: at most ``|K|`` successes.  (``D`` is a superset of "all of ``S`` at
   target": the window succeeds whenever that stronger goal could be met, with a shorter
   rank and smaller layers.)
3. **Relaxation certifies infeasibility.**  Removing positioners only removes guard
   conjuncts, so a plan of the whole, restricted to the moves of ``S``, is a plan of
   ``R(S)``.  If ``R(S)`` has none, neither has the whole problem: ``S`` names the
   positioners involved.  ``R(S)`` is solved from the start itself, so the certificate
   does not depend on the route taken.
4. **The last window is the monolithic method.**  ``S = K`` with every positioner outside
   ``K`` frozen adds no guard (no conflict pair leaves ``K``): ``C(K, c)`` is the exact
   problem of ``K`` from ``c``.  The configuration graph is undirected (every allowed move
   can be undone: the tables are symmetrised), and ``c`` was reached from the start, so
   ``K`` at target is reachable from ``c`` iff from the start; if even the weaker goal ``D``
   is unreachable from ``c``, so is ``K`` at target, and ``K`` is infeasible.

So "infeasible" is only ever answered with a certificate, and every move is a guarded
move; the budgets (``ctx.check_budget`` inside every fixpoint) bound the cost of the
larger windows and end the run with status "unknown".

References
----------
- M. Fabian et al., local modular and compositional supervisory synthesis (the
  abstraction/relaxation arguments); A. Vahidi et al. 2006.
- C. Sayres et al., kaiju (SDSS-V path planning: local, not exact — the contrast).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .coordination import CoordinationModel, conflict_components
from .plan import Move
from .planner import solve_window
from .problem import Problem

__all__ = ["solve_local", "window_sizes", "nearest_members"]


def window_sizes(total: int) -> list[int]:
    """1, 4, 7, 13, 19, then ×1.5, ending with ``total`` (the whole component)."""
    out, s = [], 1
    base = [1, 4, 7, 13, 19]
    for s in base:
        if s < total:
            out.append(s)
    s = 19
    while True:
        s = int(s * 1.5)
        if s >= total:
            break
        out.append(s)
    out.append(total)
    return out


def nearest_members(problem: Problem, p: int, component: list[int], size: int) -> list[int]:
    """The ``size`` members of ``component`` whose bases are nearest ``p``'s (ties: index)."""
    comp = np.asarray(component)
    d = np.linalg.norm(problem.bases[comp] - problem.bases[p], axis=1)
    idx = np.lexsort((comp, np.round(d, 6)))
    return sorted(int(q) for q in comp[idx[:size]])


def solve_local(problem: Problem, model: CoordinationModel, stats: dict[str, Any], *,
                supervisor: bool = False) -> tuple[list[Move] | None, Any]:
    """``(moves, None)`` with a move sequence start → target, or ``(None, (S, how))``."""
    c = problem.start.copy()
    moves: list[Move] = []
    rank_of = {p: i for i, p in enumerate(model.order)}
    comps = conflict_components(problem)
    stats.update(components=len(comps), largest_component=max(len(k) for k in comps), windows=0,
                 largest_window=0, window_sizes={}, relaxed_checks=0)
    for comp in comps:
        for p in sorted(comp, key=rank_of.__getitem__):
            if np.array_equal(c[p], problem.target[p]):
                continue
            for size in window_sizes(len(comp)):
                members = comp if size >= len(comp) else nearest_members(problem, p, comp, size)
                done = [q for q in members if q == p or np.array_equal(c[q], problem.target[q])]
                goal = model.state(done, problem.target)  # p at target, finished members stay
                res = solve_window(model, members, c, c, supervisor=supervisor, goal=goal)
                stats["windows"] += 1
                stats["largest_window"] = max(stats["largest_window"], len(members))
                if res.feasible:
                    key = str(len(members))
                    stats["window_sizes"][key] = stats["window_sizes"].get(key, 0) + 1
                    moves.extend(res.moves)
                    c = apply_moves_from(problem, c, res.moves)
                    break
                if len(members) == len(comp):
                    return None, (comp, "exhaustive symbolic search of their conflict component")
                if len(members) > 1:
                    stats["relaxed_checks"] += 1
                    relaxed = solve_window(model, members, None, problem.start, want_moves=False)
                    if not relaxed.feasible:
                        return None, (members, "exhaustive symbolic search of this relaxed subproblem")
    return moves, None


def apply_moves_from(problem: Problem, c: np.ndarray, moves: list[Move]) -> np.ndarray:
    """The configuration after ``moves`` from ``c``."""
    kin = problem.kinematics
    out = c.copy()
    for p, joint, d in moves:
        out[p] = kin.step(out[p], joint, d)
    return out
