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
(:func:`supcoord.testing.explicit_search.optimal_makespan_naive`, which it equals on small cases).

References
----------
- J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
  transition relations, 1991 (early quantification).
"""

from __future__ import annotations

import itertools
import time
from typing import Any, Sequence

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
    opts = np.array(options)
    vv, ii, jj = (g.ravel() for g in np.meshgrid(np.arange(len(options)), np.arange(n), np.arange(n), indexing="ij"))
    out = np.zeros((len(options), len(options), n, n), dtype=bool)
    for u, du in enumerate(options):  # one call per move of a: every move of b, every pair of positions
        sel = np.nonzero(valid[u][ii] & valid[vv, jj])[0]
        hit = motion_collides(problem.kin(a), (0.0, 0.0), pos[ii[sel]], du, problem.kin(b), off, pos[jj[sel]],
                              opts[vv[sel]], problem.buffers[a] + problem.buffers[b])
        flat = np.zeros(len(options) * n * n, dtype=bool)
        flat[sel] = ~hit
        out[u] = flat.reshape(len(options), n, n)
    cache[key] = out
    return out


def optimal_makespan(problem: Problem, *, members: Sequence[int] | None = None, budget: Budget | None = None,
                     backend: str = "auto", want_path: bool = False) -> dict[str, Any]:
    """``{"makespan": k or None, "layers": [...nodes], "seconds", "bdd_nodes"}`` (module
    docstring); with ``want_path`` also ``"path"``: the configurations ``c_0 = start, …, c_k =
    target`` of one fastest plan (``(N, J)`` arrays; None when unreachable).

    ``members``: search the sub-problem of these positioners with every other one removed
    (the relaxation of :mod:`.windows`: a plan of the whole, restricted to them, is a plan
    of it); the path's other rows stay at their start.
    """
    t0 = time.perf_counter()
    kin = problem.kinematics
    robots = list(range(problem.n)) if members is None else sorted({int(p) for p in members})
    inside = set(robots)
    options = _options(problem)
    pos = kin.all_positions()
    nxt = successor_table(kin, options)
    valid = nxt >= 0
    order = cutwidth_order(problem, robots)
    ctx = Context(backend, budget=budget)
    for p in order:
        for name, jt in zip(var_names(problem, p), kin.joints):
            ctx.add_variable(name, jt.steps)
    names = {p: var_names(problem, p) for p in robots}

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

    steps = {(p, u): delta_rel(p, u) for p in robots for u in range(len(options))}
    conjuncts: list[tuple[set[int], BDD]] = []
    for p in robots:
        r = ctx.false
        for u in range(len(options)):
            r |= steps[(p, u)]
        conjuncts.append(({p}, r))
    for k, (a, b) in enumerate(problem.pairs):
        a, b = int(a), int(b)
        if a not in inside or b not in inside:
            continue
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
    last_use = {p: max(i for i, (s, _) in enumerate(conjuncts) if p in s) for p in robots}
    quantify_after: dict[int, list[str]] = {}
    for p, i in last_use.items():
        quantify_after.setdefault(i, []).extend(ctx.bits(names[p]))
    every = [n for p in robots for n in names[p]]

    def image(x: BDD, k: int) -> BDD:
        for i, (_, rel) in enumerate(conjuncts):
            ctx.check_budget("optimal makespan", iteration=k)  # one image can take minutes
            q = quantify_after.get(i, [])
            x = ctx.and_exist(x, rel, q) if q else x & rel  # ∃ x_p as soon as nothing else reads it
        return ctx.unprime(x, every)

    def config(c: np.ndarray) -> BDD:
        return ctx.assignment({n: int(v) for p in robots for n, v in zip(names[p], c[p])})

    start, goal = config(problem.start), config(problem.target)
    frontier, seen, sizes, layers = start, start, [1], [start]
    k = 0
    while frontier & goal == ctx.false:
        ctx.check_budget("optimal makespan", iteration=k)
        frontier = image(frontier, k) & ~seen  # F(k+1) = Img(F(k)) \ W(k)
        if frontier == ctx.false:
            out = {"makespan": None, "layers": sizes, "seconds": time.perf_counter() - t0,
                   "bdd_nodes": ctx.peak_nodes()}
            return {**out, "path": None} if want_path else out
        seen |= frontier
        sizes.append(len(frontier))
        if want_path:
            layers.append(frontier)
        k += 1
    out = {"makespan": k, "layers": sizes, "seconds": time.perf_counter() - t0, "bdd_nodes": ctx.peak_nodes()}
    if want_path:
        out["path"] = _path_back(ctx, problem, robots, names, layers, conjuncts, every)
    return out


def _path_back(ctx: Context, problem: Problem, robots: list[int], names: dict[int, list[str]], layers: list[BDD],
               conjuncts: list[tuple[set[int], BDD]], every: list[str]) -> list[np.ndarray]:
    """One fastest path: from the target (in the last layer) back through the layers, each time
    a configuration of the layer before with a step of ``T`` to the one chosen after it."""
    c = problem.start.astype(np.int64).copy()
    c[robots] = problem.target[robots]
    path = [c.copy()]
    for layer in reversed(layers[:-1]):
        x = layer & ctx.assignment({n: int(v) for p in robots for n, v in zip(names[p], c[p])}, primed=True)
        for _, rel in conjuncts:
            x = x & rel
        values = ctx.pick(ctx.exist(every, x, primed=True), every)
        if values is None:  # cannot happen: the layer was the image's source
            raise RuntimeError("internal error: no predecessor in the breadth-first layers")
        c = c.copy()
        for p in robots:
            c[p] = [values[n] for n in names[p]]
        path.append(c.copy())
    return path[::-1]
