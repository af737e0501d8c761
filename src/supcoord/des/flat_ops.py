"""Array algorithms on flat explicit generators: breadth-first numbering, successor
tables and look-ups of packed states.

- :func:`successor_table`: ``T[q, k] = δ(q, σ_k)`` (``-1`` where undefined) when it fits
  in memory: a state's successors in event order are one row, so traversals and
  writers need no sorting.
- :func:`bfs_order`: the states reachable from ``q0`` in breadth-first order, the
  successors of a state in event order (the numbering of
  :func:`~supcoord.des.symbolic.to_explicit`), a layer at a time with array
  operations; past a number of layers (long, thin graphs) the rest is one traversal by
  SciPy's ``breadth_first_order`` from the current layer.
- :class:`KeyIndex`: the position of each of many packed keys (one ``uint64`` or a row
  of them) in a set of keys, by a hash table with linear probing built and probed
  with array operations: a few passes over the queries, instead of a sort.

References
----------
- T. H. Cormen, C. E. Leiserson, R. L. Rivest, C. Stein, *Introduction to
  Algorithms*, 3rd ed., MIT Press 2009, §22.2 (breadth-first search), §11.4 (open
  addressing).
- SciPy ``scipy.sparse.csgraph.breadth_first_order`` (compressed sparse rows,
  neighbours visited in row order).
"""

from __future__ import annotations

import numpy as np

__all__ = ["successor_table", "bfs_order", "KeyIndex", "TABLE_CELLS", "distinct", "first_occurrences"]

#: largest successor table (states × events) built, in cells
TABLE_CELLS = 200_000_000
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


def distinct(a: np.ndarray) -> np.ndarray:
    """The distinct values of ``a``, sorted (by one sort: NumPy's hashing ``unique`` was
    ten times slower on millions of integers)."""
    s = np.sort(a)
    return s[np.concatenate(([True], s[1:] != s[:-1]))] if len(s) else s


def first_occurrences(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct values of ``a`` and the position of each one's first occurrence,
    in order of first occurrence."""
    order = np.argsort(a, kind="stable")
    s = a[order]
    first = np.concatenate(([True], s[1:] != s[:-1])) if len(s) else np.zeros(0, dtype=bool)
    where = order[first]
    by_position = np.argsort(where, kind="stable")
    return s[first][by_position], where[by_position]


def successor_table(n: int, n_events: int, src: np.ndarray, ev: np.ndarray, dst: np.ndarray,
                    columns: np.ndarray | None = None) -> np.ndarray | None:
    """``T[q, j] = δ(q, σ_columns[j])`` or ``-1`` (``None`` beyond :data:`TABLE_CELLS`)."""
    if n * max(n_events, 1) > TABLE_CELLS:
        return None
    dtype = np.int32 if n < 2**31 else np.int64
    table = np.full((n, n_events), -1, dtype=dtype)
    table[src, ev] = dst
    if columns is not None:
        table = table[:, columns]
    return table


def bfs_order(n: int, src: np.ndarray, ev_rank: np.ndarray, dst: np.ndarray, start: int,
              layers: int = 2048) -> np.ndarray:
    """The states reachable from ``start`` in breadth-first order, each state's
    successors in the order of ``ev_rank`` (``0…E-1``); element ``k`` is the state numbered ``k``."""
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    n_events = int(ev_rank.max()) + 1 if len(ev_rank) else 1
    table = successor_table(n, n_events, src, ev_rank, dst)
    if table is None:
        order = np.lexsort((ev_rank, src))
        targets = dst[order]
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(src, minlength=n), out=indptr[1:])
    seen = np.zeros(n, dtype=bool)
    seen[start] = True
    out = [np.array([start], dtype=np.int64)]
    frontier = out[0]
    while len(frontier):
        if len(out) > layers:
            out.append(_bfs_rest(n, src, ev_rank, dst, seen, frontier))
            break
        if table is not None:
            t = table[frontier].ravel()
            t = t[t >= 0]
        else:
            first, counts = indptr[frontier], indptr[frontier + 1] - indptr[frontier]
            total = int(counts.sum())
            t = targets[np.repeat(first - (np.cumsum(counts) - counts), counts) + np.arange(total)]
        t = t[~seen[t]]
        if not len(t):
            break
        frontier = first_occurrences(t)[0].astype(np.int64)  # in order of discovery
        seen[frontier] = True
        out.append(frontier)
    return np.concatenate(out)


def _bfs_rest(n: int, src: np.ndarray, ev_rank: np.ndarray, dst: np.ndarray, seen: np.ndarray,
              frontier: np.ndarray) -> np.ndarray:
    """The breadth-first continuation after ``frontier``: a virtual state ``n`` leads to
    the frontier in its order, edges into states already numbered are dropped."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import breadth_first_order

    keep = ~seen[dst]
    s = np.concatenate((src[keep], np.full(len(frontier), n, dtype=np.int64)))
    r = np.concatenate((ev_rank[keep], np.arange(len(frontier), dtype=np.int64)))
    d = np.concatenate((dst[keep], frontier))
    order = np.lexsort((r, s))
    indptr = np.zeros(n + 2, dtype=np.int64)
    np.cumsum(np.bincount(s, minlength=n + 1), out=indptr[1:])
    # float64 weights: SciPy converts other types, and the conversion may sort each row
    graph = csr_matrix((np.ones(len(d)), d[order], indptr), shape=(n + 1, n + 1))
    visit = breadth_first_order(graph, n, directed=True, return_predecessors=False)
    return visit[1 + len(frontier):].astype(np.int64)


def _hash(keys: np.ndarray) -> np.ndarray:
    if keys.ndim == 1:
        return keys * _GOLDEN
    h = np.zeros(len(keys), dtype=np.uint64)
    for j in range(keys.shape[1]):
        h = (h ^ keys[:, j]) * _GOLDEN
    return h


class KeyIndex:
    """Positions of packed keys: ``KeyIndex(keys).find(queries)[i]`` is the ``j`` with
    ``keys[j] == queries[i]`` (``-1`` if none).  Keys are ``uint64`` (one per row) or
    rows of them (``(n, words)``); they must be distinct."""

    def __init__(self, keys: np.ndarray):
        self.keys = keys
        n = len(keys)
        self.bits = max(4, (2 * n).bit_length())
        self.mask = np.uint64((1 << self.bits) - 1)
        self.slots = np.full(1 << self.bits, -1, dtype=np.int64)
        pos = self._start(keys)
        pending = np.arange(n, dtype=np.int64)
        while len(pending):
            p = pos[pending]
            free = self.slots[p] < 0
            slot, first = first_occurrences(p[free])
            self.slots[slot] = pending[free][first]
            placed = np.zeros(n, dtype=bool)
            placed[pending[free][first]] = True
            pending = pending[~placed[pending]]
            pos[pending] = (pos[pending] + np.uint64(1)) & self.mask

    def _start(self, keys: np.ndarray) -> np.ndarray:
        return (_hash(keys) >> np.uint64(64 - self.bits)) & self.mask

    def find(self, queries: np.ndarray) -> np.ndarray:
        out = np.full(len(queries), -1, dtype=np.int64)
        pos = self._start(queries)
        pending = np.arange(len(queries), dtype=np.int64)
        while len(pending):
            slot = self.slots[pos[pending]]
            filled = slot >= 0
            pending, slot = pending[filled], slot[filled]
            same = self.keys[slot] == queries[pending]
            if same.ndim > 1:
                same = same.all(axis=1)
            out[pending[same]] = slot[same]
            pending = pending[~same]
            pos[pending] = (pos[pending] + np.uint64(1)) & self.mask
        return out
