"""Projection refinement: over-approximations of the configurations reachable from the
start (or co-reachable to the target) on overlapping groups of positioners.

The verdict of the coupled model depends on positions only (:mod:`.settled`): ``q0`` is
forcible exactly when the target configuration is reachable from the start in the graph
of **configurations**, where ``P_i`` may turn one step in direction ``s`` when, for every
neighbour ``j``, the pair ``(p_i, p_j)`` allows it: the swept move is free of ``j``'s arm
and, if ``j`` is in ``P_i``'s safety zone, ``P_i``'s priority lets it turn that way
(``h`` clockwise when it outranks ``j``, ``l`` counter-clockwise when ``j`` outranks it;
``v``/``w`` when the zone is empty).  So a move's guard is a conjunction of pair tables
``A_ijs[p_i, p_j]`` (:func:`pair_tables`).

For a family of groups ``G`` (the closed neighbourhoods ``{i} ∪ N(i)``), keep a set
``R_G`` of projections onto ``G``, initially every projection, and recompute each in turn
as the projections reachable from the start's inside ``G`` by moves of ``G``'s members,
where

- every state stays inside the projection of every other ``R_H`` onto ``G ∩ H``, and
- ``P_i ∈ G`` may move from ``y`` when some ``w ∈ R_{H_i}`` (``H_i`` the neighbourhood of
  ``i``) agrees with ``y`` on ``G ∩ H_i`` and allows the move (the positions of ``i``'s
  neighbours outside ``G`` are then some that ``R_{H_i}`` admits);

and keep ``R_G := R_G ∩ (that set)``, until no set shrinks.  **Soundness**, by induction
over the recomputations: every reachable configuration ``x`` projects into every ``R_H``
(true of "every projection"; a path from the start to ``x`` projects onto ``G`` into a
path whose states lie inside every projection and whose moves are allowed by ``x``'s own
neighbours, ``x|H_i ∈ R_{H_i}``).  So if the target's projection lies outside some
``R_G``, the target is unreachable: "not forcible", with ``G`` as the certificate.  The
sets only shrink, so they are sound at every moment, and the refinement may stop at any
time (a budget) with a sound answer.

**Backward**, the same with predecessor moves from the target (a move's guard read at
the state it leaves): every configuration from which the target is reachable projects
into every ``B_G``; the start outside some ``B_G`` is another certificate, and a search
for a witness may drop every configuration outside some ``B_G`` (it cannot reach the
target).  Moves are not reversible in general: the reverse step's guard reads the pair
tables at the arm's new position and with the other direction's priority.

References
----------
- P. Cousot, R. Cousot, Abstract interpretation, POPL 1977 (over-approximating fixpoints).
- E. M. Clarke, O. Grumberg, D. E. Long, Model checking and abstraction, TOPLAS 16(5),
  1994 (existential abstraction: an abstract move wherever some concrete one exists).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..bdd.context import BDD, Context
from .coupled import CoupledModel

__all__ = ["Projections", "pair_tables", "neighbourhood_groups", "refine", "proj_bdd"]

Tables = dict[tuple[int, int, int], np.ndarray]


def pair_tables(model: CoupledModel) -> Tables:
    """``A[(i, j, s)][p, q]``: a step of ``P_i`` from ``p`` in direction ``s`` (±1) is
    allowed by its neighbour ``j`` at ``q`` (swept move free; ``j`` in the zone only if
    ``P_i``'s priority lets it turn that way)."""
    r = model.inst.priority
    out = {}
    for i in range(model.inst.size):
        for j in model.neighbours[i]:
            for s in (1, -1):
                ok = r[i] < r[j] if s > 0 else r[i] > r[j]
                out[(i, j, s)] = ~model.swept[(i, j, s)] & (~model.zone[(i, j)] | ok)
    return out


def neighbourhood_groups(model: CoupledModel) -> list[tuple[int, ...]]:
    """The distinct closed neighbourhoods ``{i} ∪ N(i)``, sorted, in the order of ``i``."""
    out: list[tuple[int, ...]] = []
    for i in range(model.inst.size):
        g = tuple(sorted([i, *model.neighbours[i]]))
        if g not in out:
            out.append(g)
    return out


@dataclass
class Projections:
    """Over-approximations ``sets[k]`` of the reachable (``forward``) or co-reachable
    projections onto ``groups[k]`` (0-based positioners, axes in that order), and the first
    group whose set excludes the target's (the start's) projection: a certificate."""

    groups: list[tuple[int, ...]]
    sets: list[np.ndarray]
    forward: bool
    rounds: int = 0
    excluded: tuple[int, ...] | None = None
    fixpoint: bool = False

    def admits(self, pos: tuple[int, ...], moved: int | None = None) -> bool:
        """Whether every set holds the projection of configuration ``pos``; with ``moved``,
        ``pos`` differs from a configuration every set holds in that positioner's arm
        only, so only the sets of the groups holding it are read."""
        return all(s[tuple(pos[i] for i in g)] for g, s in zip(self.groups, self.sets)
                   if moved is None or moved in g)

    def sizes(self) -> list[int]:
        """Projections kept per group."""
        return [int(s.sum()) for s in self.sets]


def _broadcast(table: np.ndarray, group: tuple[int, ...], a: int, b: int) -> np.ndarray:
    """``table[p_a, p_b]`` as an array broadcast on ``group``'s axes."""
    ia, ib = group.index(a), group.index(b)
    shape = [1] * len(group)
    shape[ia], shape[ib] = table.shape
    return (table if ia < ib else table.T).reshape(shape)


def _project(values: np.ndarray, source: tuple[int, ...], group: tuple[int, ...]) -> np.ndarray:
    """``values`` over ``source`` projected (∃) onto ``source ∩ group``, broadcast on ``group``."""
    drop = tuple(a for a, v in enumerate(source) if v not in group)
    kept = [v for v in source if v in group]
    p = values.any(axis=drop) if drop else values
    ordered = sorted(kept, key=group.index)
    p = np.transpose(p, [kept.index(v) for v in ordered])
    shape = [1] * len(group)
    for v in ordered:
        shape[group.index(v)] = values.shape[0]
    return p.reshape(shape)


class _Refiner:
    def __init__(self, model: CoupledModel, groups: list[tuple[int, ...]], forward: bool) -> None:
        self.model, self.groups, self.forward = model, groups, forward
        self.tables = pair_tables(model)
        self.n = model.inst.steps
        self.home = {}
        for i in range(model.inst.size):  # the smallest group holding i and all its neighbours
            cover = [k for k, g in enumerate(groups) if {i, *model.neighbours[i]} <= set(g)]
            self.home[i] = min(cover, key=lambda k: len(groups[k])) if cover else None
        nxt = model._next
        self.after = {s: np.asarray(nxt[s]) for s in (1, -1)}  # after[s][p]: p moved by s
        self.before = {s: np.argsort(self.after[s]) for s in (1, -1)}  # before[s][q]: the p moved onto q
        self.seed = tuple(model.inst.start if forward else model.inst.target)
        self.goal = tuple(model.inst.target if forward else model.inst.start)

    def enabled(self, sets: list[np.ndarray], k: int, i: int, s: int) -> np.ndarray:
        """Where in ``groups[k]`` a step of ``P_i`` in direction ``s`` may be taken."""
        return self.enabled_on(sets, self.groups[k], i, s)

    def enabled_on(self, sets: list[np.ndarray], group: tuple[int, ...], i: int, s: int) -> np.ndarray:
        """Where in ``group`` (any sorted group) a step of ``P_i`` in direction ``s`` may be
        taken: allowed by ``i``'s neighbours in ``group`` and by some positions of the
        others that ``i``'s home set admits (broadcast on ``group``'s axes)."""
        model = self.model
        mask = np.ones((1,) * len(group), dtype=bool)
        for j in model.neighbours[i]:
            if j in group:
                mask = mask & _broadcast(self.tables[(i, j, s)], group, i, j)
        outside = [j for j in model.neighbours[i] if j not in group]
        if outside:
            h = self.home[i]
            if h is None:  # no group knows i's neighbourhood: each outside pair alone
                for j in outside:
                    mask = mask & self.tables[(i, j, s)].any(axis=1).reshape(
                        [self.n if v == i else 1 for v in group])
            else:
                home = self.groups[h]
                e = sets[h].copy()
                for j in model.neighbours[i]:
                    e &= _broadcast(self.tables[(i, j, s)], home, i, j)
                mask = mask & _project(e, home, group)
        return mask

    def inside(self, sets: list[np.ndarray], group: tuple[int, ...], skip: int | None = None) -> np.ndarray:
        """The projections onto ``group`` that every set but ``sets[skip]`` admits."""
        inside = np.ones((self.n,) * len(group), dtype=bool)
        for h, other in enumerate(self.groups):
            if h != skip and set(other) & set(group):
                inside &= _project(sets[h], other, group)
        return inside

    def recompute(self, sets: list[np.ndarray], k: int, check: Callable[[], None] | None = None) -> np.ndarray:
        """The projections onto ``groups[k]`` reached from the seed's by the group's moves;
        ``check`` is called before each sweep (a budget may raise there).

        Chaotic iteration: each step's image is added to the set at once, so a sweep
        follows a step of every arm in turn (Gauss–Seidel), and the sweeps stop when one
        adds nothing: the least fixpoint, the set a breadth-first search reaches, in a few
        sweeps instead of one per layer."""
        group = self.groups[k]
        inside = self.inside(sets, group, skip=k)
        steps = [(a, s, np.broadcast_to(self.enabled(sets, k, i, s), inside.shape))
                 for a, i in enumerate(group) for s in (1, -1)]
        reached = np.zeros_like(inside)
        reached[tuple(self.seed[i] for i in group)] = True
        reached &= inside
        count, grown = int(reached.sum()), True
        while grown:
            if check is not None:
                check()
            for a, s, mask in steps:
                if self.forward:  # y = x moved: x enabled and reached
                    reached |= np.take(reached & mask, self.before[s], axis=a) & inside
                else:  # x enabled and x moved reached
                    reached |= mask & np.take(reached, self.after[s], axis=a) & inside
            last, count = count, int(reached.sum())
            grown = count > last
        return reached & sets[k]


def refine(model: CoupledModel, *, forward: bool = True, groups: list[tuple[int, ...]] | None = None,
           within: Projections | None = None, max_rounds: int = 20,
           check: Callable[[], None] | None = None) -> Projections:
    """Projection refinement of the module docstring, up to its fixpoint or a certificate.

    Parameters
    ----------
    model : CoupledModel
        The instance.
    forward : bool
        True: reachable from the start (certificate: the target's projection excluded);
        False: co-reachable to the target by predecessor moves (the start's excluded).
    groups : list of tuple of int, optional
        Groups of positioners (0-based, sorted); None: :func:`neighbourhood_groups`, or
        ``within``'s groups.
    within : Projections, optional
        Sets of the other direction to start from instead of every projection: the
        result then over-approximates the configurations on some path from the start to
        the target (each reachable and co-reachable), still a certificate when it
        excludes the goal's projection.
    max_rounds : int
        Sweeps over the groups at most; the sets are sound after any number.
    check : callable, optional
        Called before each group's recomputation and each sweep of it (a
        budget check may raise there).

    Returns
    -------
    Projections
        The sets, the number of sweeps, ``excluded`` (the certificate, or None) and
        whether the fixpoint was reached.

    Examples
    --------
    >>> from supcoord.paper.run import coupled_instance
    >>> model = CoupledModel(coupled_instance(3, 8, 0))
    >>> refine(model).excluded is None  # the 3-positioner instance is forcible
    True
    """
    if within is not None:
        groups = within.groups
    groups = neighbourhood_groups(model) if groups is None else [tuple(sorted(g)) for g in groups]
    work = _Refiner(model, groups, forward)
    sets = ([np.ones((work.n,) * len(g), dtype=bool) for g in groups] if within is None
            else [s.copy() for s in within.sets])
    out = Projections(groups, sets, forward)
    stale = set(range(len(groups)))  # groups whose inputs changed since their last recomputation
    while stale and out.rounds < max_rounds:
        out.rounds += 1
        for k in range(len(groups)):
            if k not in stale:
                continue
            stale.discard(k)
            if check is not None:
                check()
            new = work.recompute(sets, k, check)
            if not new[tuple(work.goal[i] for i in groups[k])]:
                sets[k] = new
                out.excluded = groups[k]
                return out
            if (new != sets[k]).any():
                sets[k] = new
                stale.update(h for h, g in enumerate(groups) if h != k and set(g) & set(groups[k]))
    out.fixpoint = not stale
    return out


def proj_bdd(proj: Projections, ctx: Context, var: Callable[[int], str]) -> BDD:
    """The configurations every set of ``proj`` admits, as a BDD over the position
    variables ``var(i)`` (0-based ``i``)."""
    from .settled_bound import _array_bdd

    out = ctx.true
    for group, values in zip(proj.groups, proj.sets):
        out &= _array_bdd(ctx, values, [var(i) for i in group])
    return out
