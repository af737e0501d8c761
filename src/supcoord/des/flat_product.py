"""The accessible synchronous product of flat explicit generators, and reachability
on explicit graphs, with array operations.

:func:`flat_sync` builds ``Reach(G1 ∥ … ∥ Gk)``: a product state is the tuple of
component states, coded as the mixed-radix integer ``Σ qi · stride_i``; an event
moves every component that has it (and is defined there in all of them) and leaves
the others; the states are found breadth-first a layer at a time, each layer one pass
per component over all events (a component's successor row is one table look-up).
The result keeps the component states of every product state, so that questions about
the components (is ``σ`` enabled in the plants?) are array look-ups too.

:meth:`Graph.reach` is ``Reach_W(S)`` (forwards) or ``CoReach_W(S)`` (backwards, on
the reversed edges), restricted to some edges, layer by layer over rows of edges built
once; past a number of layers the rest is one SciPy traversal from a virtual state.

References
----------
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer
  2019, §2.4 (synchronous product).
- T. H. Cormen et al., *Introduction to Algorithms*, 3rd ed., MIT Press 2009, §22.2.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .flat import FlatGenerator
from .flat_ops import distinct, successor_table
from .generator import Event, merge_alphabets

__all__ = ["FlatProduct", "Graph", "flat_sync", "MAX_CODES"]

#: largest number of product state codes (``Π |Qi|``) the explicit product handles
MAX_CODES = 1 << 28
_CHUNK = 1 << 16  # frontier states expanded at a time


@dataclass
class FlatProduct:
    """``Reach(G1 ∥ … ∥ Gk)``: state ``j`` is the tuple ``states[j]`` of component states
    (state 0 the initial one), transitions ``src, ev, dst`` over ``events``."""

    components: list[FlatGenerator]
    events: list[Event]
    states: np.ndarray  # (n, k) component states
    src: np.ndarray
    ev: np.ndarray
    dst: np.ndarray

    @property
    def n_states(self) -> int:
        return len(self.states)

    def has(self, i: int) -> np.ndarray:
        """``has[g]``: whether component ``i`` has event ``g``."""
        names = {e.name for e in self.components[i].events}
        return np.array([e.name in names for e in self.events], dtype=bool)

    def enabled(self, event: int, which: Sequence[int]) -> np.ndarray:
        """The product states where every component of ``which`` that has ``event`` defines it."""
        out = np.ones(self.n_states, dtype=bool)
        name = self.events[event].name
        for i in which:
            comp = self.components[i]
            local = next((k for k, e in enumerate(comp.events) if e.name == name), None)
            if local is None:
                continue
            defined = np.zeros(comp.n_states, dtype=bool)
            defined[comp.src[comp.ev == local]] = True
            out &= defined[self.states[:, i]]
        return out

    def marked(self) -> np.ndarray:
        out = np.ones(self.n_states, dtype=bool)
        for i, comp in enumerate(self.components):
            m = np.zeros(comp.n_states, dtype=bool)
            m[comp.marked] = True
            out &= m[self.states[:, i]]
        return out


def flat_sync(components: Sequence[FlatGenerator], check: Callable[..., None] | None = None) -> FlatProduct:
    """The accessible synchronous product (see the module docstring); the events in
    first-seen order.  :class:`InputError` if ``Π |Qi|`` exceeds :data:`MAX_CODES`."""
    comps = list(components)
    events = list(merge_alphabets(c.events for c in comps).values())
    k, n_ev = len(comps), len(events)
    empty = np.zeros(0, dtype=np.int64)
    if any(c.init is None for c in comps):
        return FlatProduct(comps, events, np.zeros((0, k), dtype=np.int64), empty, empty, empty)
    sizes = [c.n_states for c in comps]
    bound = int(np.prod([float(s) for s in sizes])) if sizes else 1
    if bound > MAX_CODES:
        raise InputError(f"the explicit product has up to {bound} states, more than {MAX_CODES}", value=bound)
    strides = np.ones(k, dtype=np.int64)
    for i in range(k - 2, -1, -1):
        strides[i] = strides[i + 1] * sizes[i + 1]
    position = {e.name: g for g, e in enumerate(events)}
    tables, columns = [], []
    for c in comps:
        t = successor_table(c.n_states, len(c.events), c.src, c.ev, c.dst)
        if t is None:
            raise InputError(f"component {c.name!r} is too large for the explicit product", value=c.n_states)
        tables.append(t)
        columns.append(np.array([position[e.name] for e in c.events], dtype=np.int64))
    start = int(sum(c.init * s for c, s in zip(comps, strides)))
    index_of = np.full(bound, -1, dtype=np.int32)  # product state code -> state number, -1: not found yet
    index_of[start] = 0
    layers = [np.array([start], dtype=np.int64)]
    count = 1
    edges: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    frontier = layers[0]
    while len(frontier):
        found = []
        for lo in range(0, len(frontier), _CHUNK):
            f = frontier[lo:lo + _CHUNK]
            ok = np.ones((len(f), n_ev), dtype=bool)
            delta = np.zeros((len(f), n_ev), dtype=np.int64)
            for i, (t, cols) in enumerate(zip(tables, columns)):
                q = (f // strides[i]) % sizes[i]
                succ = t[q].astype(np.int64)  # (frontier, local events)
                ok[:, cols] &= succ >= 0
                delta[:, cols] += (succ - q[:, None]) * strides[i]
            rows, g = np.nonzero(ok)
            s = f[rows]
            d = s + delta[rows, g]
            edges.append((s, g, d))
            found.append(d)
        d = np.concatenate(found) if found else empty
        frontier = distinct(d[index_of[d] < 0])
        if not len(frontier):
            break
        index_of[frontier] = np.arange(count, count + len(frontier), dtype=np.int32)
        count += len(frontier)
        layers.append(frontier)
        if check is not None:
            check("product", layer=len(layers), states=count)
    codes = np.concatenate(layers)
    src = index_of[np.concatenate([e[0] for e in edges])].astype(np.int64)
    ev = np.concatenate([e[1] for e in edges]).astype(np.int64)
    dst = index_of[np.concatenate([e[2] for e in edges])].astype(np.int64)
    states = np.stack([(codes // strides[i]) % sizes[i] for i in range(k)], axis=1) if k else \
        np.zeros((len(codes), 0), dtype=np.int64)
    return FlatProduct(comps, events, states, src, ev, dst)


class Graph:
    """The edges ``src → dst`` of ``n`` states, with their compressed rows in either
    direction built once, for repeated reachability questions."""

    def __init__(self, n: int, src: np.ndarray, dst: np.ndarray):
        self.n, self.src, self.dst = n, src, dst
        self._rows: dict[bool, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def rows(self, backwards: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(indptr, targets, edge)``: the edges leaving each state (entering, ``backwards``)."""
        if backwards not in self._rows:
            a, b = (self.dst, self.src) if backwards else (self.src, self.dst)
            order = np.argsort(a, kind="stable")
            indptr = np.zeros(self.n + 1, dtype=np.int64)
            np.cumsum(np.bincount(a, minlength=self.n), out=indptr[1:])
            self._rows[backwards] = (indptr, b[order], order)
        return self._rows[backwards]

    def reach(self, start: np.ndarray, within: np.ndarray | None = None, edges: np.ndarray | None = None,
              backwards: bool = False, layers: int = 4096) -> np.ndarray:
        """The states reachable from the mask ``start ∩ within`` along the edges selected
        by the mask ``edges`` (all by default) inside ``within`` (everything by default),
        as a mask; ``backwards`` follows the edges in reverse (co-reachability)."""
        indptr, targets, edge = self.rows(backwards)
        seen = start & within if within is not None else start.copy()
        frontier = np.flatnonzero(seen)
        for _ in range(layers):
            if not len(frontier):
                return seen
            first, counts = indptr[frontier], indptr[frontier + 1] - indptr[frontier]
            at = np.repeat(first - (np.cumsum(counts) - counts), counts) + np.arange(int(counts.sum()))
            t = targets[at]
            keep = ~seen[t]
            if edges is not None:
                keep &= edges[edge[at]]
            if within is not None:
                keep &= within[t]
            frontier = distinct(t[keep])
            seen[frontier] = True
        if len(frontier):  # a long, thin graph: the rest in one SciPy traversal from the frontier
            from scipy.sparse import csr_matrix
            from scipy.sparse.csgraph import breadth_first_order

            a, b = (self.dst, self.src) if backwards else (self.src, self.dst)
            keep = np.ones(len(a), dtype=bool) if edges is None else edges.copy()
            if within is not None:
                keep &= within[a] & within[b]
            s = np.concatenate((a[keep], np.full(len(frontier), self.n, dtype=np.int64)))
            d = np.concatenate((b[keep], frontier))
            graph = csr_matrix((np.ones(len(d)), (s, d)), shape=(self.n + 1, self.n + 1))
            seen[breadth_first_order(graph, self.n, directed=True, return_predecessors=False)[1:]] = True
        return seen
