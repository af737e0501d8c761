"""Enumerating symbolic generators in bulk: a state set or a transition relation
becomes an array of assignments in one pass over its BDD.

:func:`assignments` walks a BDD ``u`` level by level over its care bits, carrying all
partial assignments at once: at a care level, an assignment whose node tests that
bit splits into its low and high child, one whose node lies deeper (the bit is free)
is doubled with both values, one that reaches ``FALSE`` is dropped.  In a reduced BDD
every node other than ``FALSE`` has a satisfying completion, so no level carries more
rows than the result: the cost is ``O(|u| · bits)`` array operations plus one visit
of each BDD node, not one BDD operation per state.

:func:`to_flat` exports the accessible part of a
:class:`~supcoord.des.symbolic.SymbolicGenerator` this way: the state set ``Z``
(given, or ``Reach(q0)`` from images of whole frontiers), then for each event ``σ``
the pairs ``T_σ = Z(x) ∧ R_σ(x, x'_W) ∧ Z(x)[x_W := x'_W]`` as rows ``(x, x'_W)``
(the target is ``x`` with ``W`` replaced), the marked states ``Z ∧ Qm``; rows are
matched to state numbers by sorting, and the states are numbered breadth-first from
``q0`` with events in alphabet order.  Budgets are checked between steps with the
stage ``"export"``.

References
----------
- R. E. Bryant, Graph-based algorithms for Boolean function manipulation, IEEE TC 1986
  (satisfying assignments of a reduced BDD).
- J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
  transition relations, VLSI 1991 (images of whole frontiers).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..bdd.context import BDD, Context, ThrottledCheck
from ..errors import InputError
from .flat import FlatGenerator, renumber
from .flat_ops import KeyIndex, bfs_order, distinct

__all__ = ["NodeTable", "assignments", "to_flat", "reachable_states", "state_names"]

_DEEP = np.iinfo(np.int64).max  # the level of the terminal
GROUP = 4096  # value combinations labelled by one table in state names


class NodeTable:
    """The nodes of BDDs as arrays: ``level[i]``, ``low[i]``, ``high[i]`` (references
    ``2·i + complemented``; node 0 is ``TRUE``, so reference 0 is ``TRUE`` and 1 is
    ``FALSE``).  Nodes seen once are kept for later BDDs of the same manager."""

    def __init__(self, bdd: Any):
        self.bdd = bdd
        self._index: dict[int, int] = {}
        self._level: list[int] = [_DEEP]
        self._low: list[int] = [0]
        self._high: list[int] = [0]
        self._arrays: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def ref(self, u: BDD) -> int:
        """The reference of ``u``, adding its nodes to the table."""
        if u.var is None:
            return 0 if u == self.bdd.true else 1
        pending: list[tuple[int, Any, Any]] = []
        stack = [u]
        index = self._index
        while stack:
            f = stack.pop()
            if f.var is None:
                continue
            reg = ~f if f.negated else f
            key = int(reg)
            if key in index:
                continue
            index[key] = len(self._level)
            self._level.append(reg.level)
            lo, hi = reg.low, reg.high
            pending.append((index[key], lo, hi))
            self._low.append(0)
            self._high.append(0)
            stack.append(lo)
            stack.append(hi)
        for i, lo, hi in pending:
            self._low[i], self._high[i] = self._edge(lo), self._edge(hi)
        if pending:
            self._arrays = None
        return self._edge(u)

    def _edge(self, f: Any) -> int:
        if f.var is None:
            return 0 if f == self.bdd.true else 1
        reg = ~f if f.negated else f
        return 2 * self._index[int(reg)] + (1 if f.negated else 0)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self._arrays is None:
            self._arrays = (np.array(self._level, dtype=np.int64), np.array(self._low, dtype=np.int64),
                            np.array(self._high, dtype=np.int64))
        return self._arrays


class _Layout:
    """Where each bit of each variable sits in a packed key: a variable's value is a
    field of one ``uint64`` word (MSB first); a key is one word or a row of them."""

    def __init__(self, ctx: Context, variables: Sequence[str]):
        self.variables = list(variables)
        self.field: dict[str, tuple[int, int, int]] = {}  # variable -> (word, shift, width)
        word, used = 0, 0
        for v in self.variables:
            width = ctx.vars[v].width
            if used + width > 64:
                word, used = word + 1, 0
            self.field[v] = (word, 64 - used - width, width)
            used += width
        self.words = word + 1

    def mask(self, names: Sequence[str]) -> np.ndarray:
        m = np.zeros(self.words, dtype=np.uint64)
        for v in names:
            word, shift, width = self.field[v]
            m[word] |= np.uint64(((1 << width) - 1) << shift)
        return m

    def values(self, codes: np.ndarray, v: str) -> np.ndarray:
        word, shift, width = self.field[v]
        return ((codes[:, word] >> np.uint64(shift)) & np.uint64((1 << width) - 1)).astype(np.int64)


def _expand(ctx: Context, u: BDD, layout: _Layout, names: Sequence[str], primed: Sequence[str],
            table: NodeTable) -> tuple[np.ndarray, np.ndarray]:
    """Every assignment of ``u`` as packed codes: the bits of ``names`` (unprimed) and
    of ``primed`` (primed, at the place of their unprimed twins) in ``layout``."""
    care: list[tuple[int, int, int, int]] = []  # (level, which code, word, bit)
    support: set[str] = set()
    for which, group in ((0, names), (1, primed)):
        for n in group:
            v = ctx.vars[n]
            word, shift, width = layout.field[n]
            bits = v.primed_bits if which else v.bits
            support.update(bits)
            for k, b in enumerate(bits):
                care.append((ctx.bdd.level_of_var(b), which, word, shift + width - 1 - k))
    care.sort()
    extra = set(ctx.bdd.support(u)) - support
    if extra:
        raise InputError(f"the set depends on bits outside its variables: {sorted(extra)[:5]}", value=sorted(extra))
    root = table.ref(u)
    level, low, high = table.arrays()
    refs = np.array([root], dtype=np.int64)
    codes = [np.zeros((1 if root != 1 else 0, layout.words), dtype=np.uint64) for _ in range(2)]
    if root == 1:
        return codes[0], codes[1]
    used = (0, 1) if primed else (0,)
    for lvl, which, word, bit in care:
        node, neg = refs >> 1, refs & 1
        here = level[node] == lvl
        lo = np.where(here, low[node] ^ neg, refs)
        hi = np.where(here, high[node] ^ neg, refs)
        keep_lo, keep_hi = lo != 1, hi != 1
        refs = np.concatenate((lo[keep_lo], hi[keep_hi]))
        for j in used:
            ones = codes[j][keep_hi]
            if j == which:
                ones[:, word] |= np.uint64(1 << bit)
            codes[j] = np.concatenate((codes[j][keep_lo], ones))
    if not primed:
        codes[1] = np.zeros((len(refs), layout.words), dtype=np.uint64)
    return codes[0], codes[1]


def assignments(ctx: Context, u: BDD, names: Sequence[str], primed_names: Sequence[str] = (),
                table: NodeTable | None = None) -> np.ndarray:
    """Every assignment of ``u`` as a row of values: one column per variable of
    ``names`` (unprimed bits), then one per variable of ``primed_names`` (primed bits).
    ``u`` must depend on those bits only."""
    table = table or NodeTable(ctx.bdd)
    layout = _Layout(ctx, list(dict.fromkeys(list(names) + list(primed_names))))
    x, p = _expand(ctx, u, layout, names, primed_names, table)
    cols = [layout.values(x, v) for v in names] + [layout.values(p, v) for v in primed_names]
    return np.stack(cols, axis=1) if cols else np.zeros((len(x), 0), dtype=np.int64)


def _key(codes: np.ndarray) -> np.ndarray:
    return codes[:, 0] if codes.shape[1] == 1 else codes


def reachable_states(sg, check=None) -> BDD:
    """``Reach(q0)`` of ``sg`` by images of whole frontiers."""
    reach = frontier = sg.init & sg.invariant
    ctx, layer = sg.ctx, 0
    while frontier != ctx.false:
        new = ctx.false
        for e in sg.events:
            new |= sg.post(frontier, e)
        frontier = new & ~reach
        reach |= frontier
        layer += 1
        if check is not None:
            check("export", layer=layer, step="reachable")
    return reach


def to_flat(sg, states: BDD | None = None, max_states: int = 1_000_000, name: str | None = None) -> FlatGenerator:
    """The accessible part of ``sg`` as a :class:`FlatGenerator` (see the module
    docstring); ``states``, when given, is a set containing the accessible states
    (a supervisor's own state set).  :class:`InputError` beyond ``max_states`` states."""
    ctx, variables = sg.ctx, list(sg.variables)
    check = ThrottledCheck(ctx)
    name = name or sg.name
    events = sg.alphabet
    empty = np.zeros(0, dtype=np.int64)
    if sg.init & sg.invariant == ctx.false:
        return FlatGenerator(name, events, 0, empty, empty, empty, None, empty, None)
    z = (reachable_states(sg, check) if states is None else states) & sg.invariant
    count = ctx.count(z, variables)
    if count > max_states:
        raise InputError(f"{sg.name!r} has {count} states to enumerate, more than {max_states}", value=max_states)
    table, layout = NodeTable(ctx.bdd), _Layout(ctx, variables)
    codes, _ = _expand(ctx, z, layout, variables, (), table)
    check("export", iteration=0, step="states", states=len(codes))
    index = KeyIndex(_key(codes))
    src, ev, dst = [], [], []
    primed_z: dict[tuple[str, ...], BDD] = {}
    for k, (e, rel) in enumerate(sg.events.items()):
        writes = tuple(v for v in dict.fromkeys(rel.writes) if v in layout.field)
        zp = primed_z.get(writes)
        if zp is None:
            zp = primed_z[writes] = ctx.prime(z, writes)
        x, p = _expand(ctx, z & rel.relation & zp, layout, variables, writes, table)
        if len(x):
            src.append(index.find(_key(x)))
            dst.append(index.find(_key((x & ~layout.mask(writes)) | p)))
            ev.append(np.full(len(x), k, dtype=np.int64))
        check("export", iteration=k + 1, step="transitions", event=e)
    marked = distinct(index.find(_key(_expand(ctx, z & sg.marked, layout, variables, (), table)[0])))
    init = int(index.find(_key(_expand(ctx, z & sg.init, layout, variables, (), table)[0]))[0])
    cat = lambda parts: np.concatenate(parts) if parts else empty
    flat = FlatGenerator(name, events, len(codes), cat(src), cat(ev), cat(dst), init, marked, None)
    order = bfs_order(flat.n_states, flat.src, flat.ev, flat.dst, init)
    check("export", iteration=len(sg.events) + 1, step="numbering")
    rows = codes[order]
    return renumber(flat, order, name, state_names(variables, [layout.values(rows, v) for v in variables]))


def state_names(variables: Sequence[str], columns: Sequence[np.ndarray]) -> list[str]:
    """``"v1=3,v2=0"`` per state from the value column of each variable (``"0"`` without
    variables).  Neighbouring variables are labelled together (one table look-up for
    each group of values, at most :data:`GROUP` combinations), so a state's name is the
    join of a few strings, not of one per variable."""
    if not variables:
        return ["0"] * (len(columns[0]) if columns else 1)
    parts: list[list[str]] = []
    k = 0
    while k < len(variables):
        group, size = [k], int(columns[k].max()) + 1 if len(columns[k]) else 1
        while k + len(group) < len(variables):
            nxt = int(columns[k + len(group)].max()) + 1 if len(columns[k]) else 1
            if size * nxt > GROUP:
                break
            group.append(k + len(group))
            size *= nxt
        code = np.zeros(len(columns[k]), dtype=np.int64)
        domains = []
        for j in group:
            d = int(columns[j].max()) + 1 if len(columns[j]) else 1
            code = code * d + columns[j]
            domains.append(range(d))
        table = np.array([",".join(f"{variables[j]}={x}" for j, x in zip(group, combo))
                          for combo in itertools.product(*domains)], dtype=object)
        parts.append(table[code].tolist())
        k += len(group)
    return parts[0] if len(parts) == 1 else list(map(",".join, zip(*parts)))
