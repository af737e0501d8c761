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
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..bdd.context import BDD, Budget, Context
from ..geometry.collision import prefiltered_motion_collides
from ..problems.problem import Problem
from .graph_order import cutwidth_order
from .caches import caches_for
from .guards import successor_table, table_bdd, var_names

__all__ = ["optimal_makespan", "MakespanResult"]


def _options(problem: Problem) -> list[np.ndarray]:
    return [np.array(d, dtype=np.int64) for d in itertools.product((0, 1, -1), repeat=problem.kinematics.n_joints)]


def _free_table(problem: Problem, k: int, options: list[np.ndarray], valid: np.ndarray) -> np.ndarray:
    """``F[u, v, i, j]`` of pair ``k`` (False where a delta leaves the joint ranges)."""
    cache = caches_for(problem).free_simultaneous
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
    nxt = successor_table(kin, options)
    distances = problem.tables().distance_view(k)  # [position of a, position of b]
    for u, du in enumerate(options):  # one call per move of a: every move of b, every pair of positions
        sel = np.nonzero(valid[u][ii] & valid[vv, jj])[0]
        # the end-point distances settle most entries (a collision at an end, or clear by the
        # motions' sweep lengths); the others are sampled as motion_collides samples them
        hit = prefiltered_motion_collides(problem.kin(a), (0.0, 0.0), pos, ii[sel], nxt[u, ii[sel]], du,
                                          problem.kin(b), off, jj[sel], nxt[vv[sel], jj[sel]], opts[vv[sel]],
                                          float(problem.buffers[a] + problem.buffers[b]), distances)
        flat = np.zeros(len(options) * n * n, dtype=bool)
        flat[sel] = ~hit
        out[u] = flat.reshape(len(options), n, n)
    cache[key] = out
    return out


@dataclass(frozen=True)
class MakespanResult:
    """What :func:`optimal_makespan` found: ``makespan`` (steps; None: the target is
    unreachable), ``layers`` (the size of each breadth-first layer ``F(k)``, configurations),
    ``seconds`` (wall clock), ``bdd_nodes`` (peak live nodes) and, when asked for, ``path``:
    the configurations ``c_0 = start, …, c_k = target`` of one fastest plan (``(N, J)`` index
    arrays; None when unreachable or not asked for)."""

    makespan: int | None
    layers: list[int]
    seconds: float
    bdd_nodes: int
    path: list[np.ndarray] | None = None

    def to_json(self) -> dict[str, Any]:
        """The result as a JSON object (the path as nested lists of lattice indices)."""
        out: dict[str, Any] = {"makespan": self.makespan, "layers": list(self.layers), "seconds": self.seconds,
                               "bdd_nodes": self.bdd_nodes}
        if self.path is not None:
            out["path"] = [np.asarray(c).tolist() for c in self.path]
        return out



def optimal_makespan(problem: Problem, *, members: Sequence[int] | None = None, budget: Budget | None = None,
                     backend: str = "auto", want_path: bool = False) -> MakespanResult:
    """The least number of simultaneous steps from the start to the target (module docstring).

    Parameters
    ----------
    problem : Problem
        The problem (lattice indices; lengths in mm).
    members : sequence of int, optional
        Search the sub-problem of these positioners with every other one removed (the
        relaxation of :mod:`.windows`: a plan of the whole, restricted to them, is a plan of
        it); the path's other rows stay at their start.
    budget : Budget, optional
        Node, time (s) and memory limits of the search.
    backend : str, default "auto"
        The BDD backend of ``dd``.
    want_path : bool, default False
        Also reconstruct one fastest plan (``path``), which keeps every layer.

    Returns
    -------
    MakespanResult
        The makespan (steps, None when unreachable), the layer sizes, the time, the peak
        BDD nodes and, with ``want_path``, one fastest plan.

    Raises
    ------
    BudgetExceeded
        The budget ran out before the search ended.

    Examples
    --------
    >>> from supcoord.problems import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [40, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 8.0, "steps": 8},
    ...                    "collision": {"buffer": 1.0}, "start": [0, 0], "target": [2, 7]})
    >>> r = optimal_makespan(p, want_path=True)
    >>> r.makespan, len(r.path)
    (2, 3)

    References
    ----------
    J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
    transition relations, 1991.
    """
    t0 = time.perf_counter()
    robots = list(range(problem.n)) if members is None else sorted({int(p) for p in members})
    T = _Transitions(problem, robots, Context(backend, budget=budget))
    ctx = T.ctx
    start, goal = T.config(problem.start), T.config(problem.target)
    frontier, seen, sizes, layers = start, start, [1], [start]
    k = 0
    while frontier & goal == ctx.false:
        ctx.check_budget("optimal makespan", iteration=k)
        frontier = T.image(frontier, k) & ~seen  # F(k+1) = Img(F(k)) \ W(k)
        if frontier == ctx.false:
            return MakespanResult(None, sizes, time.perf_counter() - t0, ctx.peak_nodes())
        seen |= frontier
        sizes.append(len(frontier))
        if want_path:
            layers.append(frontier)
        k += 1
    seconds, nodes = time.perf_counter() - t0, ctx.peak_nodes()
    path = _path_back(ctx, problem, robots, T.names, layers, T.conjuncts, T.every) if want_path else None
    return MakespanResult(k, sizes, seconds, nodes, path)


class _Transitions:
    """The simultaneous transition relation ``T`` of the positioners ``robots`` as a
    conjunction: one conjunct per robot (its own steps) and one per pair inside (the free
    table of their steps), in the order of the variables; :meth:`image` quantifies each
    robot's current bits after the last conjunct that reads them."""

    def __init__(self, problem: Problem, robots: list[int], ctx: Context):
        self.problem, self.robots, self.ctx = problem, robots, ctx
        kin = problem.kinematics
        self.options = _options(problem)
        self.pos = kin.all_positions()
        self.nxt = successor_table(kin, self.options)
        self.valid = self.nxt >= 0
        order = cutwidth_order(problem, robots)
        for p in order:
            for name, jt in zip(var_names(problem, p), kin.joints):
                ctx.add_variable(name, jt.steps)
        self.names = {p: var_names(problem, p) for p in robots}
        self.conjuncts = self._conjuncts()
        where = {p: i for i, p in enumerate(order)}
        self.conjuncts.sort(key=lambda sc: min(where[p] for p in sc[0]))
        last_use = {p: max(i for i, (s, _) in enumerate(self.conjuncts) if p in s) for p in robots}
        self.quantify_after: dict[int, list[str]] = {}
        for p, i in last_use.items():
            self.quantify_after.setdefault(i, []).extend(ctx.bits(self.names[p]))
        self.every = [n for p in robots for n in self.names[p]]

    def _delta_rel(self, p: int, u: int) -> BDD:
        """``[x'_p = x_p + u]`` as a BDD over the current and next bits of ``p`` (where ``p``'s
        own constraints allow it: obstacles, held in place)."""
        ctx, pos, nxt, names = self.ctx, self.pos, self.nxt, self.names
        r = ctx.false
        ok = self.valid[u].copy()
        if p in self.problem.unary():
            sel = np.nonzero(ok)[0]
            ok[sel] = ~self.problem.own_motion_blocked(p, pos[sel], self.options[u])
        for i in np.nonzero(ok)[0]:
            cur = {nm: int(v) for nm, v in zip(names[p], pos[i])}
            new = {nm: int(v) for nm, v in zip(names[p], pos[nxt[u, i]])}
            r |= ctx.assignment(cur) & ctx.assignment(new, primed=True)
        return r

    def _conjuncts(self) -> list[tuple[set[int], BDD]]:
        """One conjunct per robot, then one per neighbour pair with both members inside."""
        ctx, problem, robots, n_options = self.ctx, self.problem, self.robots, len(self.options)
        steps = {(p, u): self._delta_rel(p, u) for p in robots for u in range(n_options)}
        out: list[tuple[set[int], BDD]] = []
        for p in robots:
            r = ctx.false
            for u in range(n_options):
                r |= steps[(p, u)]
            out.append(({p}, r))
        inside = set(robots)
        for k, (a, b) in enumerate(problem.pairs):
            a, b = int(a), int(b)
            if a not in inside or b not in inside:
                continue
            free = _free_table(problem, k, self.options, self.valid)
            c = ctx.false
            for u in range(n_options):
                for v in range(n_options):
                    if not free[u, v].any():
                        continue
                    f = table_bdd(ctx, free[u, v].reshape(problem.kinematics.shape * 2),
                                  self.names[a] + self.names[b])
                    c |= steps[(a, u)] & steps[(b, v)] & f
            out.append(({a, b}, c))
        return out

    def image(self, x: BDD, k: int) -> BDD:
        """The configurations one simultaneous step after ``x`` (``k``: the layer, for budgets)."""
        ctx = self.ctx
        for i, (_, rel) in enumerate(self.conjuncts):
            ctx.check_budget("optimal makespan", iteration=k)  # one image can take minutes
            q = self.quantify_after.get(i, [])
            x = ctx.and_exist(x, rel, q) if q else x & rel  # ∃ x_p as soon as nothing else reads it
        return ctx.unprime(x, self.every)

    def config(self, c: np.ndarray) -> BDD:
        """The BDD of configuration ``c`` restricted to the robots."""
        return self.ctx.assignment({n: int(v) for p in self.robots for n, v in zip(self.names[p], c[p])})


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
