"""The settled states of the coupled model, symbolically: the graph :mod:`.settled` searches.

A state of the coupled plant (:mod:`.coupled`) is *settled* when no uncontrollable event
is defined there; :func:`settle` fires the due ``k``/``e`` events of a state and counts
them (``D``).  A settled state is encoded by the positions and one bit per positioner,
``stale_i = [lvl_i = 2 ∧ c_i = 1]`` (two neighbours were in the zone, one left, ``m`` not
yet fired): every other level is ``min(c_i, 2)``, so ``lvl_i = 0 ⟺ c_i = 0``.  A
controllable event of ``P_i`` followed by the settling it causes is one relation per
weight ``1 + D``: it writes ``pos_i`` and the stale bits of ``P_i`` and its neighbours
and reads the positions around them; the relations of one write set and weight are
merged.  The guards are the coupled plant's, read on settled states:

- ``v``/``w``: ``c_i = 0`` and the swept move free of every neighbour;
- ``h``/``l``: ``c_i ≥ 1``, ``P_i`` outranks (is outranked by) everyone in its zone, move free;
- ``m``: ``stale_i`` (``lvl_i = 2 ∧ c_i ≤ 1`` on a settled state), to ``stale_i = 0``, weight 1.

After a move of ``P_i`` its level starts from 0, so it settles to ``min(c_i', 2)`` with
``d_i = min(c_i', 2)`` events; a neighbour ``j`` keeps its level ``L`` (0, 1, or 2 when
``c_j ≥ 2`` or stale) and settles with ``c_j'``: to 0 by one ``e`` if ``c_j' = 0``, to
``max(L, 1)`` (stale if ``L = 2``) if ``c_j' = 1``, to 2 by ``2 − L`` events if ``c_j' ≥ 2``.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011.
- J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
  transition relations, VLSI 1991 (one relation per event and weight).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from ..bdd.context import BDD, Context, ThrottledCheck
from ..des.generator import event_key
from ..errors import InputError
from ..synthesis.image_step import ImageStep
from .coupled import CoupledModel, positioner_order
from .events import positioner_events
from .literal import ring_step
from .settled_bound import GROUP_SIZE, HPartition, PatternBound

__all__ = ["State", "Move", "SettledGraph", "settle", "target_in_zone", "check_settled_route", "successor_events"]

State = tuple[tuple[int, ...], tuple[int, ...]]  # (positions, levels)


def settle(model: CoupledModel, pos: tuple[int, ...], lvl: tuple[int, ...],
           near: int | None = None) -> tuple[tuple[int, ...], int]:
    """``(levels of settle(x), D(x))`` for the state ``x = (pos, lvl)``; ``near``: ``x`` is one
    event from a settled state, an event of that positioner, so only it and its neighbours
    can have events pending (the others' levels and counts are those of a settled state)."""
    out, total = list(lvl), 0
    for i in range(len(lvl)) if near is None else (near, *model.neighbours[near]):
        level = lvl[i]
        c = model.count(i, pos)
        if c == 0:
            if level >= 1:
                out[i], total = 0, total + 1
        elif level < min(c, 2):
            out[i], total = min(c, 2), total + min(c, 2) - level
    return tuple(out), total


@dataclass(frozen=True)
class Move:
    """Controllable events of one positioner restricted to one weight ``1 + D``, with
    their forward and backward images (renaming by ``AndAbstract`` with the identity)."""

    event: str
    weight: int
    relation: BDD
    writes: tuple[str, ...]
    forward: ImageStep
    backward: ImageStep


def target_in_zone(model: CoupledModel) -> tuple[int, int] | None:
    """A pair of positioners inside each other's safety zone at their targets, or None."""
    target = tuple(model.inst.target)
    for i in range(model.inst.size):
        for j in model.in_zone(i, target):
            return (i, j) if i < j else (j, i)
    return None


def check_settled_route(model: CoupledModel) -> None:
    """Raise :class:`InputError` if the start or the target collides, or if the target has
    an arm in another's safety zone (:func:`target_in_zone`)."""
    model.check()
    pair = target_in_zone(model)
    if pair is not None:
        raise InputError(f"the settled route needs a target configuration with no arm in another's safety zone "
                         f"(P{pair[0] + 1} and P{pair[1] + 1} are closer than {model.geo.zone} mm there, so a "
                         f"collision event is pending at the target and supcon may remove it); use the "
                         f"monolithic route", value=[pair[0] + 1, pair[1] + 1], where="target")


class SettledGraph:
    """The settled states of a coupled instance symbolically: ``pos{i}`` and ``stale{i}``
    per positioner (blocks in :func:`~.coupled.positioner_order`), one :class:`Move` per
    event and weight, the start ``settle(q0)`` and its ``D``, and the target.  The target
    configuration must have no arm in another's safety zone (:func:`target_in_zone`).
    ``report``: more items for every progress report while the relations are built (the
    verdict a checked forcing string proved, so that a run stopped there still says it)."""

    def __init__(self, model: CoupledModel, ctx: Context | None = None, order: str = "auto",
                 group_size: int = GROUP_SIZE, bound: PatternBound | None = None,
                 report: Mapping[str, Any] | None = None) -> None:
        check_settled_route(model)
        self.model, self.inst = model, model.inst
        self.bound = bound if bound is not None else PatternBound(model, group_size)
        self.ctx = ctx = ctx or Context()
        n, size = self.inst.steps, self.inst.size
        self._depth = {i: k for k, i in enumerate(positioner_order(model, order))}  # block's place in the order
        for i in positioner_order(model, order):
            ctx.add_variable(self.pos(i), n)
            ctx.add_variable(self.stale(i), 2)
        self.variables = tuple(v for i in positioner_order(model, order) for v in (self.pos(i), self.stale(i)))
        self._zone = {(i, j): model._table_bdd(ctx, i, j, model.zone[(i, j)])
                      for i in range(size) for j in model.neighbours[i]}
        self._st = [ctx.eq(self.stale(i), 1) for i in range(size)]
        self._stp = [ctx.eq(self.stale(i), 1, primed=True) for i in range(size)]
        self._raw: list[tuple[str, int, BDD, tuple[str, ...]]] = []
        self._identities: dict[tuple[str, ...], BDD] = {}
        check = ThrottledCheck(ctx)
        for i in range(size):
            check("settled relations", positioner=i + 1, of=size, **(report or {}))
            self._add_moves(i)
        self.moves = self._merged(self._raw, lambda: check("settled relations", merging=True, **(report or {})))
        del self._raw
        self.target_raw: State = (tuple(self.inst.target), (0,) * size)
        self.target = self.code(self.target_raw)
        start = (tuple(self.inst.start), (0,) * size)
        self.start_raw: State = start
        self.start_levels, self.start_cost = settle(model, *start)
        self.start = self.code((start[0], self.start_levels))
        self.max_weight = max((m.weight for m in self.moves), default=1)

    def _merged(self, moves: list[tuple[str, int, BDD, tuple[str, ...]]], check: Callable[[], None]) -> list[Move]:
        """One relation per write set and weight (the events of one positioner that move
        its arm share their write set): fewer, slightly larger images; ``check`` is called
        before each."""
        groups: dict[tuple[tuple[str, ...], int], list[tuple[str, BDD]]] = {}
        for event, weight, relation, writes in moves:
            groups.setdefault((writes, weight), []).append((event, relation))
        out = []
        for (writes, weight), group in groups.items():
            check()
            rel = self.ctx.false
            for _, r in group:
                rel |= r
            out.append(self._move("|".join(e for e, _ in group), weight, rel, writes))
        return out

    def _move(self, event: str, weight: int, relation: BDD, writes: tuple[str, ...]) -> Move:
        ctx = self.ctx
        bits, primed = tuple(ctx.bits(writes)), tuple(ctx.bits(writes, primed=True))
        ident = self._identities.get(writes)
        if ident is None:
            ident = self._identities[writes] = ctx.identity(writes)
        steps = [ImageStep(event, relation, q, ident, r, forward, frozenset(writes), frozenset(writes), clip=False)
                 for q, r, forward in ((bits, primed, True), (primed, bits, False))]
        return Move(event, weight, relation, writes, *steps)

    @staticmethod
    def pos(i: int) -> str:
        return f"pos{i + 1}"

    @staticmethod
    def stale(i: int) -> str:
        return f"stale{i + 1}"

    def code(self, state: State) -> BDD:
        """The BDD cube of a settled state ``(pos, lvl)``."""
        pos, lvl = state
        values = {}
        for i, (p, level) in enumerate(zip(pos, lvl)):
            values[self.pos(i)] = p
            values[self.stale(i)] = int(level == 2 and self.model.count(i, pos) == 1)
        return self.ctx.assignment(values)

    # -- relations ---------------------------------------------------------------

    def _counts(self, j: int, moved: int | None = None, skip: int | None = None) -> list[BDD]:
        """``[c_j = 0, c_j = 1, c_j ≥ 2]``; ``pos_moved`` primed (after its move); ``skip`` left out."""
        ctx = self.ctx
        zones = []
        for k in self.model.neighbours[j]:
            if k == skip:
                continue
            z = self._zone[(j, k)]
            zones.append(ctx.prime(z, [self.pos(moved)]) if moved in (j, k) else z)
        one = ctx.false
        for z in zones:
            one |= z
        two = ctx.false
        for a, b in itertools.combinations(zones, 2):
            two |= a & b
        return [~one, one & ~two, two]

    def _settle_by_weight(self, i: int, step: BDD) -> dict[int, BDD]:
        """``{D: R ∧ step}`` for a move ``step`` of ``P_i`` (``pos_i → pos_i'``): ``R`` sets
        the stale bits of ``P_i`` and its neighbours after settling, ``D`` is the number of
        uncontrollable events that takes (module docstring).  Conjoining ``step`` first
        keeps every intermediate BDD to the moves that exist, and taking the neighbours
        from the bottom of the variable order up halves the time (19 positioners: 14 s
        against 26 s, the same relations)."""
        ctx, model = self.ctx, self.model
        new = self._counts(i, moved=i)
        parts = {d: step & new[d] & ~self._stp[i] for d in range(3)}  # lvl_i was 0: min(c_i, 2) k's
        for j in sorted(model.neighbours[i], key=self._depth.get, reverse=True):
            rest = self._counts(j, skip=i)
            before = self._zone[(j, i)]
            after = ctx.prime(before, [self.pos(i)])
            cases = [ctx.false] * 3  # by d: the case conditions of one d are disjoint
            for a, zb, za in itertools.product(range(3), (0, 1), (0, 1)):
                old_c, new_c = min(a + zb, 2), min(a + za, 2)
                where = rest[a] & (before if zb else ~before) & (after if za else ~after)
                for stale in (0, 1) if old_c == 1 else (0,):
                    level = 0 if old_c == 0 else 2 if (old_c == 2 or stale) else 1
                    if new_c == 0:
                        d, now_stale = int(level >= 1), 0
                    elif new_c == 1:
                        d, now_stale = max(1 - level, 0), int(level == 2)
                    else:
                        d, now_stale = 2 - level, 0
                    st = self._st[j] if stale else ~self._st[j]
                    stp = self._stp[j] if now_stale else ~self._stp[j]
                    cases[d] |= where & st & stp
            merged: dict[int, BDD] = {}
            for w, u in parts.items():
                for d, case in enumerate(cases):
                    v = u & case
                    if v != ctx.false:
                        merged[w + d] = merged.get(w + d, ctx.false) | v
            parts = merged
        return parts

    def _add_moves(self, i: int) -> None:
        ctx, model, inst = self.ctx, self.model, self.inst
        n, pos = inst.steps, self.pos(i)
        count = self._counts(i)
        busy = count[1] | count[2]
        top = bottom = busy
        for j in model.neighbours[i]:
            if not inst.priority[i] < inst.priority[j]:
                top &= ~self._zone[(i, j)]
            if not inst.priority[i] > inst.priority[j]:
                bottom &= ~self._zone[(i, j)]
        ev = positioner_events(i + 1)
        writes = tuple([pos, self.stale(i)] + [self.stale(j) for j in model.neighbours[i]])
        for sign, plain, escape, extra in ((1, "v", "h", top), (-1, "w", "l", bottom)):
            step = ring_step(ctx, pos, n, sign)
            for j in model.neighbours[i]:
                step &= ~model._table_bdd(ctx, i, j, model.swept[(i, j, sign)])
            if step == ctx.false:
                continue
            by_weight = self._settle_by_weight(i, step)
            for kind, guard in ((plain, count[0]), (escape, extra)):  # settled: lvl_i = 0 ⟺ c_i = 0
                g = guard & step
                if g == ctx.false:
                    continue
                for d, rel in sorted(by_weight.items()):
                    r = g & rel
                    if r != ctx.false:
                        self._raw.append((ev[kind].name, 1 + d, r, writes))
        # m: lvl_i = 2 ∧ c_i ≤ 1 in a settled state is stale_i; it leaves lvl_i = 1 = min(c_i, 2)
        self._raw.append((ev["m"].name, 1, self._st[i] & ~self._stp[i], (self.stale(i),)))

    # -- images and the bound ------------------------------------------------------

    def post(self, move: Move, x: BDD) -> BDD:
        """``{y' : ∃ y ∈ x. (y, y') ∈ move}``."""
        return move.forward.raw_image(self.ctx, x)

    def pre(self, move: Move, x: BDD) -> BDD:
        """``{y : ∃ y' ∈ x. (y, y') ∈ move}``."""
        return move.backward.raw_image(self.ctx, x)

    def distance_exact(self, cap: int | None = None, check: Callable[[], None] | None = None) -> list[BDD]:
        """``H[b]``: the states whose lower bound ``h`` (:mod:`.settled_bound`) is ``b``, for
        ``b ≤ cap`` (None: all); ``check`` is called between the pieces (a budget may raise)."""
        return self.bound.partitions(self.ctx, self.pos, cap, check)

    def h_partition(self, check: Callable[[], None] | None = None) -> HPartition:
        """``H[b]`` built on demand (:class:`~.settled_bound.HPartition`); ``check`` as there."""
        return HPartition(self.bound, self.ctx, self.pos, check)

    def heuristic(self, pos: tuple[int, ...]) -> int | None:
        """``h`` of a configuration, None where even the relaxation cannot reach the target."""
        return self.bound.value(pos)


def successor_events(model: CoupledModel, state: State, controllable: bool) -> list[tuple[str, State]]:
    """The controllable (or uncontrollable) events defined at ``state`` with their
    successors, by name (:func:`~supcoord.des.generator.event_key`)."""
    pos, lvl = state
    out = []
    for i in range(len(pos)):
        ev = positioner_events(i + 1)
        for kind, (p, level) in model.successors(i, pos, lvl).items():
            if ev[kind].controllable == controllable:
                out.append((ev[kind].name, (pos[:i] + (p,) + pos[i + 1:], lvl[:i] + (level,) + lvl[i + 1:])))
    return sorted(out, key=lambda s: event_key(s[0]))
