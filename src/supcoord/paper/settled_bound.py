"""A lower bound on the events left to the target: additive pattern databases of moves and
the collision events they leave pending.

Partition the positioners into groups of neighbours.  For one group ``P``, relax the
coupled model to the arms of ``P`` alone, positions only: ``P_i ∈ P`` may turn one step
when the swept move is free of the other arms of ``P`` and, if an arm of ``P`` is in its
zone, in the direction its priority allows (clockwise ``h`` when it outranks every arm
of ``P`` in its zone, counter-clockwise ``l`` when every one outranks it); the levels,
the ``m`` and uncontrollable events and every arm outside ``P`` are dropped.  A move of
the real model is a move of the relaxation: ``v``/``w`` need an empty zone, and ``h``/``l``
need the priority over every arm in the zone, those of ``P`` among them.

A move costs one plus a lower bound on the collision events it leaves pending: after
``v``, ``w``, ``h`` or ``l`` the mover ``P_i`` is at level 0, so in the settled graph the
edge's weight ``1 + D`` counts ``d_i = min(c_i, 2)`` of its own ``k_i`` events, and
``c_i`` is at least ``c_i^P``, the arms of ``P`` in its zone after the move.  The relaxed
move costs ``1 + min(c_i^P, 2)``, plus one for every *interior* neighbour ``j ∈ P`` of
the mover (all of ``j``'s neighbours are in ``P``, so ``c_j = c_j^P``) whose zone turns
from empty to occupied or back: in a settled state ``lvl_j = 0 ⟺ c_j = 0``, so an arm
entering an empty zone leaves ``k_j`` pending and the last arm leaving one leaves ``e_j``
pending (``j`` itself at level ≥ 1), and both are in the edge's ``D`` beside the mover's
own ``k_i``.  A non-interior ``j`` earns nothing: an arm outside ``P`` may hold its zone
occupied (and its level capped at 2).  ``d_P(x)`` is the least cost that brings the arms of
``P`` from their positions in ``x`` to their targets in that relaxed graph (Dial's
algorithm over the ``n^|P|`` configurations, on arrays).  Every event of the real model
is an edge of the relaxation of the mover's group, or moves no arm (``m``); each moves at
most one arm, of one group, and costs at least what that group charges for it (the
collision events charged are those of the mover and of its group's interior
neighbours, all distinct), so

    h(x) = Σ_P d_P(x)

is a lower bound on the weight left from ``x`` to the target (admissible), and it drops
along an edge by at most the edge's weight (consistent: A* expands every state at its
distance).  Charging the zones raises the bound where arms must pass each other: on the
12-positioner benchmark instance ``h(q0)`` goes from 23 (ring distances) to 26 (the
mover's own collision events, groups of 5; ``benchmarks/results/coupled_zones.md``) and
to 32 of the rank 37 with the interior neighbours' events and groups of 6
(``benchmarks/results/coupled_interior.md``).  Where some ``d_P(x)`` is infinite the target is
unreachable from ``x`` even in the relaxation: such states are never expanded.  Groups of
one positioner give the plain sum of ring distances.  :meth:`PatternBound.partitions`
gives ``{x : h(x) = b}`` as BDDs for the A* of :mod:`.settled`.

References
----------
- J. C. Culberson, J. Schaeffer, Pattern databases, Computational Intelligence 14(3), 1998.
- R. E. Korf, A. Felner, Disjoint pattern database heuristics, Artificial Intelligence
  134, 2002 (additivity when every operator moves one tile of one group).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..bdd.context import BDD, Context
from ..errors import InputError
from .coupled import CoupledModel

__all__ = ["GROUP_SIZE", "CERTIFICATE_SIZE", "grown_group", "neighbour_groups", "PatternBound", "HPartition"]

#: positioners per group: a database holds ``steps ** GROUP_SIZE`` distances (262,144 at
#: 8 steps); larger groups give a tighter bound (more interior positioners) for more table.
#: 6 measured fastest (``benchmarks/results/coupled_interior.md``): 7 spends more on its
#: tables and their BDDs than the tighter bound saves at 8-12 positioners
GROUP_SIZE = 6
#: positioners per group that :meth:`PatternBound.blocked_group` tries around each
#: positioner: 5 found the 19-positioner benchmark instance blocked (P1, P3, P4, P5, P13
#: in 0.6 s for its 15 distinct groups), where groups of 4 did not
CERTIFICATE_SIZE = 5
#: a database larger than this many entries is refused (memory: 1 byte an entry)
MAX_ENTRIES = 1 << 24
UNREACHABLE = np.iinfo(np.int16).max


def _check_size(size: int, where: str) -> None:
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise InputError(f"group size must be a positive integer, got {size!r}", value=size, where=where)


def grown_group(model: CoupledModel, seed: int, size: int, free: set[int]) -> list[int]:
    """At most ``size`` positioners of ``free`` grown from ``seed`` by adding, one at a time,
    the positioner with the most neighbours already in the group (ties: the lowest index)."""
    group = [seed]
    while len(group) < size:
        links = {j: sum(j in model.neighbours[i] for i in group) for j in free if j not in group}
        if not any(links.values()):
            break
        group.append(-max((v, -j) for j, v in links.items() if v > 0)[1])
    return sorted(group)


def neighbour_groups(model: CoupledModel, size: int = GROUP_SIZE) -> list[list[int]]:
    """Disjoint groups of at most ``size`` positioners covering all, each grown
    (:func:`grown_group`) from the lowest unassigned positioner."""
    _check_size(size, "group_size")
    free = set(range(model.inst.size))
    groups = []
    while free:
        group = grown_group(model, min(free), size, free)
        free.difference_update(group)
        groups.append(group)
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

    def _table(self, group: list[int], within: np.ndarray | None = None,
               outside: Callable[[int, int], np.ndarray] | None = None) -> np.ndarray:
        """Least costs to the group's targets in the relaxed graph, a move costing one plus
        the collision events it leaves pending on the mover among the group and on the
        group's interior neighbours of the mover (module docstring), by Dial's algorithm
        backward (``x`` gets ``w + d(y)`` for every allowed move ``x → y`` of cost ``w``;
        the costs are 1 to 9, so the states of cost ``L`` are final when level ``L`` is
        reached).  ``within``: the group's configurations kept (flat, None: all; a move
        must leave and reach one); ``outside(a, sign)``: where the arms outside the group
        let ``group[a]`` turn that way (flat, None: everywhere) — :mod:`.settled_sets_bound`."""
        model, n, k = self.model, self.model.inst.steps, len(group)
        grid = np.indices((n,) * k).reshape(k, -1)  # configurations, axis a = group[a]
        index = lambda cols: np.ravel_multi_index(tuple(cols), (n,) * k)  # noqa: E731
        edges = []  # (sources, destinations, costs) of each kind of move
        priority = model.inst.priority
        members = set(group)
        interior = [b for b, j in enumerate(group) if set(model.neighbours[j]) <= members]

        def occupied(b: int, conf: np.ndarray) -> np.ndarray:  # c_j > 0, j = group[b] interior
            c = np.zeros(conf.shape[1], dtype=bool)
            for bb, jj in enumerate(group):
                if jj in model.neighbours[group[b]]:
                    c |= model.zone[(group[b], jj)][conf[b], conf[bb]]
            return c

        for a, i in enumerate(group):
            for sign in (1, -1):
                # free of the group's arms, and no arm of the group in the zone that P_i
                # may not escape from in this direction (h: it outranks them, l: they it)
                ok = np.ones(grid.shape[1], dtype=bool)
                moved = grid.copy()
                moved[a] = np.asarray(model._next[sign])[grid[a]]
                zone_after = np.zeros(grid.shape[1], dtype=np.int16)  # the group's arms in P_i's zone after
                for b, j in enumerate(group):
                    if j in model.neighbours[i]:
                        ok &= ~model.swept[(i, j, sign)][grid[a], grid[b]]
                        if not (priority[i] < priority[j] if sign > 0 else priority[i] > priority[j]):
                            ok &= ~model.zone[(i, j)][grid[a], grid[b]]
                        zone_after += model.zone[(i, j)][moved[a], grid[b]]
                if outside is not None:
                    ok &= outside(a, sign)
                if within is not None:
                    ok &= within & within[index(moved)]
                cost = 1 + np.minimum(zone_after, 2)
                for b in interior:  # k_j into an empty zone, e_j out of the last arm
                    if b != a and group[b] in model.neighbours[i]:
                        cost += occupied(b, grid) != occupied(b, moved)
                edges.append((np.nonzero(ok)[0], index(moved[:, ok]), cost[ok]))
        dist = np.full(grid.shape[1], UNREACHABLE, dtype=np.int16)
        dist[index([[model.inst.target[i]] for i in group])] = 0
        level = 0
        while (dist[dist != UNREACHABLE] >= level).any():
            final = dist == level
            if final.any():
                for src, dst, cost in edges:
                    hit = final[dst]
                    np.minimum.at(dist, src[hit], (level + cost[hit]).astype(np.int16))
            level += 1
        return dist.reshape((n,) * k)

    def blocked_group(self, pos: tuple[int, ...], size: int = CERTIFICATE_SIZE) -> list[int] | None:
        """A group whose relaxation cannot bring its arms from ``pos`` to their targets, or
        None: first the partition's groups, then the group of at most ``size`` grown
        (:func:`grown_group`) around each positioner in turn.

        Every settled edge of the real model moves at most one arm, by a move of the
        relaxation of any group containing it (module docstring), so such a group proves
        the target unreachable from ``pos`` in the settled graph: no forcing string exists.
        A group that is not blocked proves nothing (the other arms may still block it);
        groups overlap freely here, since no sum is taken."""
        _check_size(size, "certificate_size")
        for group, table in zip(self.groups, self.tables):
            if table[tuple(pos[i] for i in group)] == UNREACHABLE:
                return group
        if len(self.groups) == 1:  # the one group is every positioner: nothing larger to try
            return None
        n, seen = self.model.inst.steps, {tuple(g) for g in self.groups}
        everyone = set(range(self.model.inst.size))
        for seed in range(self.model.inst.size):
            group = grown_group(self.model, seed, size, everyone)
            if tuple(group) in seen or n ** len(group) > MAX_ENTRIES:
                continue
            seen.add(tuple(group))
            if self._table(group)[tuple(pos[i] for i in group)] == UNREACHABLE:
                return group
        return None

    def value(self, pos: tuple[int, ...]) -> int | None:
        """``h`` of a configuration, None where the target is unreachable even relaxed."""
        total = 0
        for group, table in zip(self.groups, self.tables):
            d = int(table[tuple(pos[i] for i in group)])
            if d == UNREACHABLE:
                return None
            total += d
        return total

    def partitions(self, ctx: Context, var: callable, cap: int | None = None,
                   check: Callable[[], None] | None = None) -> list[BDD]:
        """``H[b] = {x : h(x) = b}`` over the position variables ``var(i)``, for ``b ≤ cap``.

        Parameters
        ----------
        ctx : Context
            Where the BDDs are built.
        var : callable
            ``var(i)``: the name of positioner ``i``'s position variable.
        cap : int, optional
            Largest ``b`` kept (None: every finite value).
        check : callable, optional
            Called before each BDD of a group's values and each sum built (a budget check
            may raise there).

        Returns
        -------
        list of BDD
            ``H[0], …, H[m]``, ``m`` the largest finite value of ``h`` or ``cap``,
            whichever is smaller.

        Examples
        --------
        >>> from supcoord.paper.run import coupled_instance
        >>> model = CoupledModel(coupled_instance(3, 8, 0))
        >>> ctx, bound = Context(), PatternBound(model)
        >>> for i in range(3):
        ...     _ = ctx.add_variable(f"p{i}", 8)
        >>> full = bound.partitions(ctx, lambda i: f"p{i}")
        >>> capped = bound.partitions(ctx, lambda i: f"p{i}", cap=3)
        >>> len(capped), capped == full[:4], len(full) > 4
        (4, True, True)
        """
        top = sum(int(t[t != UNREACHABLE].max(initial=0)) for t in self.tables)
        return HPartition(self, ctx, var, check).upto(top if cap is None else min(cap, top))


class HPartition:
    """``H[b] = {x : h(x) = b}`` as BDDs, built on demand in increasing ``b``: the A* at a
    sweep ``f`` needs only ``b ≤ f``.  With groups ``P_1, …, P_m`` and ``V_k[d]`` the
    configurations where ``d_{P_k} = d``, ``S_k[a] = ∪_d S_{k-1}[a − d] ∧ V_k[d]`` (``S_0[0]``
    every state), and ``H[b] = S_m[b]``: extending to ``b`` computes ``S_k[b]`` for
    ``k = 1, …, m``, from sums already built.  ``check()`` is called before each ``V_k[d]``
    and each ``S_k[b]`` (a budget may raise there).

    Examples
    --------
    >>> from supcoord.paper.run import coupled_instance
    >>> model = CoupledModel(coupled_instance(3, 8, 0))
    >>> ctx, bound = Context(), PatternBound(model)
    >>> for i in range(3):
    ...     _ = ctx.add_variable(f"p{i}", 8)
    >>> part = HPartition(bound, ctx, lambda i: f"p{i}")
    >>> len(part.upto(2)), len(part.upto(5)), part.upto(5)[:3] == part.upto(2)
    (3, 6, True)
    """

    def __init__(self, bound: PatternBound, ctx: Context, var: Callable[[int], str],
                 check: Callable[[], None] | None = None) -> None:
        self.ctx, self.var, self.check = ctx, var, check or (lambda: None)
        self.groups, self.tables = bound.groups, bound.tables
        self.values = [sorted(int(v) for v in np.unique(t) if v != UNREACHABLE) for t in self.tables]
        self._v: list[dict[int, BDD]] = [{} for _ in self.tables]  # V_k[d], built when first needed
        self._s: list[list[BDD]] = [[ctx.true]] + [[] for _ in self.tables]  # S_k[a], a = 0, 1, …
        self.exact: list[BDD] = []  # H[0], H[1], …

    def _value(self, k: int, d: int) -> BDD:
        if d not in self._v[k]:
            self.check()
            names = [self.var(i) for i in self.groups[k]]
            self._v[k][d] = _array_bdd(self.ctx, self.tables[k] == d, names)
        return self._v[k][d]

    def upto(self, b: int) -> list[BDD]:
        """``[H[0], …, H[b]]``, extending the sums built so far as needed."""
        false = self.ctx.false
        for a in range(len(self.exact), b + 1):
            if a > 0:
                self._s[0].append(false)
            for k in range(len(self.tables)):
                self.check()
                u = false
                for d in self.values[k]:
                    if d > a:
                        break
                    prev = self._s[k][a - d]
                    if prev != false:
                        u |= prev & self._value(k, d)
                self._s[k + 1].append(u)
            self.exact.append(self._s[-1][a])
        return self.exact[: b + 1]


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
