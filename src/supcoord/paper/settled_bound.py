"""A lower bound on the events left to the target: additive pattern databases of moves.

Partition the positioners into groups of neighbours.  For one group ``P``, relax the
coupled model to the arms of ``P`` alone, positions only: ``P_i ∈ P`` may turn one step
when the swept move is free of the other arms of ``P`` and, if an arm of ``P`` is in its
zone, in the direction its priority allows (clockwise ``h`` when it outranks every arm
of ``P`` in its zone, counter-clockwise ``l`` when every one outranks it); the levels,
the ``m`` and uncontrollable events and every arm outside ``P`` are dropped.  A move of
the real model is a move of the relaxation: ``v``/``w`` need an empty zone, and ``h``/``l``
need the priority over every arm in the zone, those of ``P`` among them.  ``d_P(x)`` is the least number of moves that
brings the arms of ``P`` from their positions in ``x`` to their targets in that relaxed
graph (a breadth-first search over the ``n^|P|`` configurations, on arrays).  Every move
of the real model is a move of the relaxation, and each event moves at most one arm,
which belongs to one group, so

    h(x) = Σ_P d_P(x)

is a lower bound on the events from ``x`` to the target (admissible) and changes by at
most one per event, which costs at least one (consistent: A* expands every state at its
distance).  Where some ``d_P(x)`` is infinite the target is unreachable from ``x`` even
in the relaxation: such states are never expanded.  Groups of one positioner give the
plain sum of ring distances.  :meth:`PatternBound.partitions` gives ``{x : h(x) = b}``
as BDDs for the A* of :mod:`.settled`.

References
----------
- J. C. Culberson, J. Schaeffer, Pattern databases, Computational Intelligence 14(3), 1998.
- R. E. Korf, A. Felner, Disjoint pattern database heuristics, Artificial Intelligence
  134, 2002 (additivity when every operator moves one tile of one group).
"""

from __future__ import annotations

import numpy as np

from ..bdd.context import BDD, Context
from ..errors import InputError
from .coupled import CoupledModel

__all__ = ["GROUP_SIZE", "neighbour_groups", "PatternBound"]

#: positioners per group: a database holds ``steps ** GROUP_SIZE`` distances (32,768 at
#: 8 steps); larger groups give a tighter bound for more table
GROUP_SIZE = 5
#: a database larger than this many entries is refused (memory: 1 byte an entry)
MAX_ENTRIES = 1 << 24
UNREACHABLE = np.iinfo(np.int16).max


def neighbour_groups(model: CoupledModel, size: int = GROUP_SIZE) -> list[list[int]]:
    """Disjoint groups of at most ``size`` positioners covering all: each grown from the
    lowest unassigned positioner by adding the unassigned positioner with the most
    neighbours already in the group (ties: the lowest index)."""
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise InputError(f"group size must be a positive integer, got {size!r}", value=size, where="group_size")
    free = set(range(model.inst.size))
    groups = []
    while free:
        group = [min(free)]
        free.discard(group[0])
        while len(group) < size:
            links = {j: sum(j in model.neighbours[i] for i in group) for j in free}
            best = max((v, -j) for j, v in links.items() if v > 0) if any(links.values()) else None
            if best is None:
                break
            group.append(-best[1])
            free.discard(-best[1])
        groups.append(sorted(group))
    return groups


class PatternBound:
    """The additive pattern databases of one instance: ``tables[k][x_P]`` = ``d_P``."""

    def __init__(self, model: CoupledModel, group_size: int = GROUP_SIZE) -> None:
        self.model = model
        self.groups = neighbour_groups(model, group_size)
        n = model.inst.steps
        if any(n ** len(g) > MAX_ENTRIES for g in self.groups):
            raise InputError(f"a pattern database of {group_size} positioners at {n} steps has more than "
                             f"{MAX_ENTRIES} entries", value=group_size, where="group_size")
        self.tables = [self._table(g) for g in self.groups]

    def _table(self, group: list[int]) -> np.ndarray:
        """Breadth-first distances to the group's targets in the relaxed graph (backward:
        ``x`` gets ``d(y) + 1`` for every allowed move ``x → y``)."""
        model, n, k = self.model, self.model.inst.steps, len(group)
        grid = np.indices((n,) * k).reshape(k, -1)  # configurations, axis a = group[a]
        index = lambda cols: np.ravel_multi_index(tuple(cols), (n,) * k)  # noqa: E731
        edges = []  # (sources, destinations) of each allowed move
        priority = model.inst.priority
        for a, i in enumerate(group):
            for sign in (1, -1):
                # free of the group's arms, and no arm of the group in the zone that P_i
                # may not escape from in this direction (h: it outranks them, l: they it)
                ok = np.ones(grid.shape[1], dtype=bool)
                for b, j in enumerate(group):
                    if j in model.neighbours[i]:
                        ok &= ~model.swept[(i, j, sign)][grid[a], grid[b]]
                        if not (priority[i] < priority[j] if sign > 0 else priority[i] > priority[j]):
                            ok &= ~model.zone[(i, j)][grid[a], grid[b]]
                moved = grid.copy()
                moved[a] = np.asarray(model._next[sign])[grid[a]]
                edges.append((np.nonzero(ok)[0], index(moved[:, ok])))
        dist = np.full(grid.shape[1], UNREACHABLE, dtype=np.int16)
        dist[index([[model.inst.target[i]] for i in group])] = 0
        frontier, level = dist == 0, 0
        while frontier.any():
            level += 1
            reached = np.zeros_like(frontier)
            for src, dst in edges:
                reached[src[frontier[dst]]] = True
            frontier = reached & (dist == UNREACHABLE)
            dist[frontier] = level
        return dist.reshape((n,) * k)

    def value(self, pos: tuple[int, ...]) -> int | None:
        """``h`` of a configuration, None where the target is unreachable even relaxed."""
        total = 0
        for group, table in zip(self.groups, self.tables):
            d = int(table[tuple(pos[i] for i in group)])
            if d == UNREACHABLE:
                return None
            total += d
        return total

    def partitions(self, ctx: Context, var: callable) -> list[BDD]:
        """``H[b] = {x : h(x) = b}`` over the position variables ``var(i)``."""
        exact = {0: ctx.true}
        for group, table in zip(self.groups, self.tables):
            by_value = {int(v): _array_bdd(ctx, table == v, [var(i) for i in group])
                        for v in np.unique(table) if v != UNREACHABLE}
            nxt: dict[int, BDD] = {}
            for a, u in exact.items():
                for d, v in by_value.items():
                    w = u & v
                    if w != ctx.false:
                        nxt[a + d] = nxt.get(a + d, ctx.false) | w
            exact = nxt
        return [exact.get(b, ctx.false) for b in range(max(exact, default=0) + 1)]


def _array_bdd(ctx: Context, mask: np.ndarray, names: list[str]) -> BDD:
    """``{x : mask[x_0, x_1, …]}`` with ``x_a`` the value of ``names[a]``, built by
    splitting on the first axis, equal sub-arrays shared."""
    memo: dict[tuple[int, bytes], BDD] = {}
    try:
        return _split(ctx, names, memo, 0, np.ascontiguousarray(mask))
    finally:
        memo.clear()  # no BDD may outlive its manager


def _split(ctx: Context, names: list[str], memo: dict, axis: int, sub: np.ndarray) -> BDD:
    if not sub.any():
        return ctx.false
    if sub.all():
        return ctx.true
    key = (axis, sub.tobytes())
    if key not in memo:
        u = ctx.false
        for p in range(sub.shape[0]):
            u |= ctx.eq(names[axis], p) & _split(ctx, names, memo, axis + 1, sub[p])
        memo[key] = u
    return memo[key]
