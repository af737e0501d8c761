"""The optimal makespan, symbolically: breadth-first search in the simultaneous semantics.

A *simultaneous step* moves every joint of every positioner by ``−1``, ``0`` or ``+1`` at
once (linearly in joint space over the step, as :mod:`supcoord.problems.validate` interpolates); it is
allowed when every neighbour pair's joint motion is collision-free.  With ``O`` the
per-step deltas ``{−1, 0, +1}^J`` and ``F_{ab}[u, v, i, j]`` = "``a`` doing ``u`` from ``i``
while ``b`` does ``v`` from ``j`` is free" (:func:`~supcoord.geometry.collision.motion_collides`)::

    T(x, x') = ⋀_p  ⋁_{u ∈ O} [x'_p = x_p + u]
             ∧ ⋀_{(a,b) ∈ N} ⋁_{u, v ∈ O} [x'_a = x_a + u] ∧ [x'_b = x_b + v] ∧ F_{ab}[u, v](x_a, x_b)

    F(0) = {start},  F(k+1) = Img(F(k)) \\ (F(0) ∪ … ∪ F(k)),
    makespan* = least k with target ∈ F(k)  (None: unreachable)

``Img(X) = ∃x. X ∧ T`` is computed with the conjuncts of ``T`` applied in variable order
and each ``x_p`` quantified as soon as no remaining conjunct reads it (early
quantification).  Every plan the planner returns is a path of ``T`` (its steps pass
the validator), so ``makespan* ≤`` its makespan: the yardstick of
``benchmarks/bench_makespan.py`` on grids too large for the explicit twin
(:func:`supcoord.testing.search.optimal_makespan_naive`, which it equals on small cases).

References
----------
- J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
  transition relations, 1991 (early quantification).
"""

from __future__ import annotations

import itertools
import time
from typing import Any

import numpy as np

from ..bdd.context import BDD, Budget, Context
from ..geometry.collision import motion_collides
from ..problems.problem import Problem
from .graph_order import cutwidth_order
from .guards import successor_table, table_bdd, var_names

__all__ = ["optimal_makespan"]


def _options(problem: Problem) -> list[np.ndarray]:
    return [np.array(d, dtype=np.int64) for d in itertools.product((0, 1, -1), repeat=problem.kinematics.n_joints)]


def _free_table(problem: Problem, k: int, options: list[np.ndarray], valid: np.ndarray) -> np.ndarray:
    """``F[u, v, i, j]`` of pair ``k`` (False where a delta leaves the joint ranges)."""
    cache = problem.__dict__.setdefault("_free_sim_cache", {})
    a, b = (int(x) for x in problem.pairs[k])
    key = problem.geometry_key(a, b)
    off = key[:2]
    if key in cache:
        return cache[key]
    kin = problem.kinematics
    pos = kin.all_positions()
    n = len(pos)
    ii, jj = (g.ravel() for g in np.meshgrid(np.arange(n), np.arange(n), indexing="ij"))
    out = np.zeros((len(options), len(options), n, n), dtype=bool)
    for u, du in enumerate(options):
        for v, dv in enumerate(options):
            sel = np.nonzero(valid[u][ii] & valid[v][jj])[0]
            hit = motion_collides(problem.kin(a), (0.0, 0.0), pos[ii[sel]], du, problem.kin(b), off, pos[jj[sel]], dv,
                                  problem.buffers[a] + problem.buffers[b])
            flat = np.zeros(n * n, dtype=bool)
            flat[sel] = ~hit
            out[u, v] = flat.reshape(n, n)
    cache[key] = out
    return out


def optimal_makespan(problem: Problem, *, budget: Budget | None = None, backend: str = "auto") -> dict[str, Any]:
    """``{"makespan": k or None, "layers": [...nodes], "seconds", "bdd_nodes"}`` (module docstring)."""
    t0 = time.perf_counter()
    kin = problem.kinematics
    options = _options(problem)
    pos = kin.all_positions()
    nxt = successor_table(kin, options)
    valid = nxt >= 0
    order = cutwidth_order(problem, range(problem.n))
    ctx = Context(backend, budget=budget)
    for p in order:
        for name, jt in zip(var_names(problem, p), kin.joints):
            ctx.add_variable(name, jt.steps)
    names = {p: var_names(problem, p) for p in range(problem.n)}

    def delta_rel(p: int, u: int) -> BDD:
        """``[x'_p = x_p + u]`` as a BDD over the current and next bits of ``p`` (where ``p``'s
        own constraints allow it: obstacles, held in place)."""
        r = ctx.false
        ok = valid[u].copy()
        if p in problem.unary():
            sel = np.nonzero(ok)[0]
            ok[sel] = ~problem.own_motion_blocked(p, pos[sel], options[u])
        for i in np.nonzero(ok)[0]:
            cur = {nm: int(v) for nm, v in zip(names[p], pos[i])}
            new = {nm: int(v) for nm, v in zip(names[p], pos[nxt[u, i]])}
            r |= ctx.assignment(cur) & ctx.assignment(new, primed=True)
        return r

    steps = {(p, u): delta_rel(p, u) for p in range(problem.n) for u in range(len(options))}
    conjuncts: list[tuple[set[int], BDD]] = []
    for p in range(problem.n):
        r = ctx.false
        for u in range(len(options)):
            r |= steps[(p, u)]
        conjuncts.append(({p}, r))
    for k, (a, b) in enumerate(problem.pairs):
        a, b = int(a), int(b)
        free = _free_table(problem, k, options, valid)
        c = ctx.false
        for u in range(len(options)):
            for v in range(len(options)):
                if not free[u, v].any():
                    continue
                f = table_bdd(ctx, free[u, v].reshape(kin.shape * 2), names[a] + names[b])
                c |= steps[(a, u)] & steps[(b, v)] & f
        conjuncts.append(({a, b}, c))
    where = {p: i for i, p in enumerate(order)}
    conjuncts.sort(key=lambda sc: min(where[p] for p in sc[0]))
    last_use = {p: max(i for i, (s, _) in enumerate(conjuncts) if p in s) for p in range(problem.n)}
    quantify_after: dict[int, list[str]] = {}
    for p, i in last_use.items():
        quantify_after.setdefault(i, []).extend(ctx.bits(names[p]))
    every = [n for p in range(problem.n) for n in names[p]]

    def image(x: BDD, k: int) -> BDD:
        for i, (_, rel) in enumerate(conjuncts):
            ctx.check_budget("optimal makespan", iteration=k)  # one image can take minutes
            q = quantify_after.get(i, [])
            x = ctx.and_exist(x, rel, q) if q else x & rel  # ∃ x_p as soon as nothing else reads it
        return ctx.unprime(x, every)

    start = ctx.assignment({n: int(v) for p in range(problem.n) for n, v in zip(names[p], problem.start[p])})
    goal = ctx.assignment({n: int(v) for p in range(problem.n) for n, v in zip(names[p], problem.target[p])})
    frontier, seen, sizes = start, start, [1]
    k = 0
    while frontier & goal == ctx.false:
        ctx.check_budget("optimal makespan", iteration=k)
        frontier = image(frontier, k) & ~seen  # F(k+1) = Img(F(k)) \ W(k)
        if frontier == ctx.false:
            return {"makespan": None, "layers": sizes, "seconds": time.perf_counter() - t0,
                    "bdd_nodes": ctx.peak_nodes()}
        seen |= frontier
        sizes.append(len(frontier))
        k += 1
    return {"makespan": k, "layers": sizes, "seconds": time.perf_counter() - t0, "bdd_nodes": ctx.peak_nodes()}
