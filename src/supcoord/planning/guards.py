"""The collision guards of the coordination model: blocked tables, the conflict graph, table BDDs.

For a neighbour pair ``k = (a, b)`` (:mod:`supcoord.geometry.collision`) and a move ``m``
of one member (the *mover*) past the other standing at ``j``::

    B_{p,m}(i, j) = W_m(i, j) ∨ W_{m̄}(step_m(i), j)

with ``W_m`` the swept table of ``m`` (:meth:`CollisionTables.swept`) and ``m̄`` the
reverse move from the end pose: the table is *symmetrised*, so a move is allowed exactly
when its reverse is and the configuration graph is undirected (:func:`blocked_table`).
The guard of the move against the neighbour is ``¬B``.

**Collision-freedom needs no state invariant.**  Every swept table contains the static
table at both ends (``W ⊇ T`` at the start and at the end pose, ``docs/geometry.md``), so
a guarded move starts and ends in configurations where no pair with the mover collides,
and pairs without the mover keep their positions.  By induction every state reachable
from a collision-free ``q0`` — and every state that reaches the collision-free target
backwards — is collision-free, and every transition between them is
swept-collision-free.  Starts and targets are collision-free (``problems/problem.py``
raises otherwise), so the reachable (and coreachable) parts of the model contain no
collision.

The *conflict graph* joins the positioners of the pairs whose tables block something
(:func:`conflict_graph`); each distinct pair table becomes a BDD on the actual bits
bottom-up from the truth table (:func:`table_bdd`).

References
----------
- R. E. Bryant, Graph-based algorithms for Boolean function manipulation, 1986.
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (positioners as DES).
"""

from __future__ import annotations

from typing import Any, Callable, Iterable, Sequence

import numpy as np

from ..bdd.context import BDD, Context
from ..geometry.collision import ENTRY_CACHE
from ..geometry.kinematics import Kinematics
from ..geometry.table_store import PackedTables, release_free_heap, remembered
from ..problems.problem import Problem

__all__ = ["blocked_table", "blocked_bits", "blocked_column", "blocked_entries", "blocked_entries_of_pairs",
           "is_blocked", "conflict_graph", "pair_graph",
           "successor_table", "table_bdd", "var_names"]

#: ``adj[p] = [(k, q, side), …]``: pair ``k = (p, q)`` with ``p`` on side ``side``
Adjacency = list[list[tuple[int, int, int]]]


#: bytes of blocked tables kept unpacked (all are kept bit-packed: :func:`blocked_bits`)
BLOCKED_CACHE_BYTES = 256 * 2**20


def _blocked_store(problem: Problem) -> PackedTables:
    store = problem.__dict__.get("_blocked_store")
    if store is None:
        store = problem.__dict__["_blocked_store"] = PackedTables(BLOCKED_CACHE_BYTES)
    return store


def blocked_table(problem: Problem, k: int, side: int) -> np.ndarray:
    """``B[m, i, j]``: move ``m`` of the pair member ``side`` (0: ``a``, 1: ``b``) from its
    position ``i`` is blocked while the other stands at ``j`` — oriented mover first,
    symmetrised with the reverse move from the end pose (module docstring).  Shared, like the
    swept tables, by the pairs of equal geometry (:meth:`Problem.pair_geometry_key`): one
    table per offset on a grid of identical robots, not one per pair.  Kept bit-packed
    (:mod:`supcoord.geometry.table_store`); the array returned is read-only, and the readers
    of single entries or columns use :func:`is_blocked` and :func:`blocked_column`, which
    read the bits without unpacking."""
    store = _blocked_store(problem)
    key = problem.pair_geometry_key(k) + (side,)
    if key in store:
        return store.get(key)
    tables, kin = problem.tables(), problem.kinematics
    w = tables.swept(k, side)
    if side == 1:
        w = np.swapaxes(w, 1, 2)  # [m, i_mover, j_other]
    pos = kin.all_positions()
    moves = kin.moves()
    out = w.copy()
    for m, (joint, delta) in enumerate(moves):
        rev = moves.index((joint, -delta))
        nxt, ok = kin.step_array(pos, joint, delta)
        idx = np.nonzero(ok)[0]
        out[m, idx] |= w[rev, kin.flat_index(nxt[idx])]  # the way back must be free too
    return store.put(key, out)


def _stored(problem: Problem, k: int, side: int) -> tuple[PackedTables, tuple]:
    """The store and key of :func:`blocked_table` ``(k, side)``, the table computed if new."""
    store = _blocked_store(problem)
    key = problem.pair_geometry_key(k) + (side,)
    if key not in store:
        blocked_table(problem, k, side)
    return store, key


def blocked_bits(problem: Problem, k: int, side: int) -> np.ndarray:
    """:func:`blocked_table` bit-packed on its last axis (read-only ``uint8``): ``B[m, i, j]``
    is bit ``7 − j % 8`` of byte ``[m, i, j // 8]`` (:meth:`PackedTables.packed`)."""
    store, key = _stored(problem, k, side)
    return store.packed(key)


def _lazy(problem: Problem, k: int, side: int) -> bool:
    """Are pair ``k``'s tables lazy (:attr:`CollisionTables.lazy`) and its blocked table not built?"""
    return problem.tables().lazy and problem.pair_geometry_key(k) + (side,) not in _blocked_store(problem)


def is_blocked(problem: Problem, k: int, side: int, m: int, i: int, j: int) -> bool:
    """``B[m, i, j]`` of :func:`blocked_table`, read from the bits (lazy tables: decided on its
    own, :func:`blocked_entries`)."""
    if _lazy(problem, k, side):
        return bool(blocked_entries(problem, k, side, [m], [i], [j])[0])
    store, key = _stored(problem, k, side)
    return store.bit(key, m, i, j)


def blocked_column(problem: Problem, k: int, side: int, m: int, j: int) -> np.ndarray:
    """``B[m, :, j]`` of :func:`blocked_table` (the mover's positions blocked by the other
    standing at ``j``), read from the bits (lazy tables: from two lines of the swept table,
    :meth:`CollisionTables.swept_line`)."""
    if _lazy(problem, k, side):
        tables, kin = problem.tables(), problem.kinematics
        joint, delta = kin.moves()[m]
        rev = kin.moves().index((joint, -delta))
        line = (lambda mv: tables.swept_line(k, 0, mv, j=j)) if side == 0 else \
            (lambda mv: tables.swept_line(k, 1, mv, i=j))
        out = line(m).copy()
        nxt, ok = kin.step_array(kin.all_positions(), joint, delta)
        idx = np.nonzero(ok)[0]
        out[idx] |= line(rev)[kin.flat_index(nxt[idx])]
        return out
    store, key = _stored(problem, k, side)
    return store.column(key, m, j)


def blocked_entries(problem: Problem, k: int, side: int, m: Sequence[int], i: Sequence[int],
                    j: Sequence[int]) -> np.ndarray:
    """``B[m, i, j]`` of :func:`blocked_table` for index lists (mover at ``i``, the other at
    ``j``), each decided on its own from the swept entries (:func:`blocked_entries_of_pairs`):
    what the readers of lazy tables use.  Remembered per problem."""
    held = _entry_cache(problem)
    g, n_pos = held.code(k, side), held.n_pos
    keys = [g + (mv * n_pos + x) * n_pos + y for mv, x, y in zip(m, i, j)]
    m, i, j = (np.asarray(v, dtype=np.int64) for v in (m, i, j))
    return remembered(held.hits, keys, lambda sel: blocked_entries_of_pairs(problem, k, side, m[sel], i[sel], j[sel]),
                      ENTRY_CACHE)


class _EntryCache:
    """A problem's remembered lazy blocked entries, one integer key per entry:
    ``code(k, side) + (m · P + i) · P + j`` (pairs of equal geometry share a code)."""

    def __init__(self, problem: Problem):
        kin = problem.kinematics
        self.problem = problem
        self.n_pos = kin.n_positions
        self.span = len(kin.moves()) * self.n_pos ** 2
        self.hits: dict[int, bool] = {}
        self._geometry: dict[tuple, int] = {}
        self._codes: dict[tuple[int, int], int] = {}

    def code(self, k: int, side: int) -> int:
        out = self._codes.get((k, side))
        if out is None:
            g = self._geometry.setdefault(self.problem.pair_geometry_key(k) + (side,), len(self._geometry))
            out = self._codes[k, side] = g * self.span
        return out


def _entry_cache(problem: Problem) -> _EntryCache:
    held = problem.__dict__.get("_blocked_entries")
    if held is None:
        held = problem.__dict__["_blocked_entries"] = _EntryCache(problem)
    return held


def blocked_entries_of_pairs(problem: Problem, k: Any, side: Any, m: Any, i: Any, j: Any) -> np.ndarray:
    """``B[m, i, j]`` of :func:`blocked_table` of pair ``k[e]`` and mover ``side[e]`` for every
    entry ``e``, decided at once from the swept entries of any pairs
    (:meth:`CollisionTables.swept_entries_of_pairs`): the entry, then (unless it is blocked
    already) the way back from the end pose.  Each is remembered (:func:`blocked_entries`)."""
    k, side, m, i, j = (np.asarray(v, dtype=np.int64).ravel() for v in np.broadcast_arrays(k, side, m, i, j))
    tables, kin = problem.tables(), problem.kinematics
    nxt, rev = _successors(problem)

    def swept(sel: np.ndarray, mv: np.ndarray, mover_at: np.ndarray) -> np.ndarray:
        on_b = side[sel] == 1
        return tables.swept_entries_of_pairs(k[sel], side[sel], mv, np.where(on_b, j[sel], mover_at),
                                             np.where(on_b, mover_at, j[sel]))

    got = swept(np.arange(len(k)), m, i)
    back = np.nonzero(~got & (nxt[m, i] >= 0))[0]  # the way back must be free too
    if len(back):
        got[back] = swept(back, rev[m[back]], nxt[m[back], i[back]])
    held = _entry_cache(problem)
    cache, code, n_pos = held.hits, held.code, held.n_pos
    if len(cache) + len(k) > ENTRY_CACHE:
        cache.clear()
    for kk, s, mv, x, y, hit in zip(k.tolist(), side.tolist(), m.tolist(), i.tolist(), j.tolist(), got.tolist()):
        cache[code(kk, s) + (mv * n_pos + x) * n_pos + y] = hit
    return got


def _successors(problem: Problem) -> tuple[np.ndarray, np.ndarray]:
    """``(nxt, rev)``: ``nxt[m, i]`` the flat position after move ``m`` from ``i`` (−1 past a
    hard stop), ``rev[m]`` the move back."""
    held = problem.__dict__.get("_successors")
    if held is None:
        kin = problem.kinematics
        moves = kin.moves()
        pos = kin.all_positions()
        nxt = np.full((len(moves), len(pos)), -1, dtype=np.int64)
        for mv, (joint, delta) in enumerate(moves):
            q, ok = kin.step_array(pos, joint, delta)
            nxt[mv, ok] = kin.flat_index(q[ok])
        rev = np.array([moves.index((joint, -delta)) for joint, delta in moves])
        held = problem.__dict__["_successors"] = (nxt, rev)
    return held


def entry_lookup(problem: Problem) -> Callable[[int, int, int, int, int], bool | None]:
    """``lookup(k, side, m, i, j)``: the remembered lazy entry ``B[m, i, j]`` of pair ``k``
    (mover ``side``), None if not decided yet (a reader's fast path)."""
    held = _entry_cache(problem)
    cache, code, n_pos = held.hits, held.code, held.n_pos
    return lambda k, side, m, i, j: cache.get(code(k, side) + (m * n_pos + i) * n_pos + j)


def _move_blocked_any(problem: Problem, k: int) -> bool:
    """Can pair ``k`` ever block a move (a collision within the motion ranges)?"""
    kin = problem.kinematics
    pos = kin.all_positions()
    for side in (0, 1):
        b = blocked_table(problem, k, side)
        for m, (joint, delta) in enumerate(kin.moves()):
            ok = kin.step_valid(pos, joint, delta)
            if b[m, ok].any():
                return True
    return bool(problem.tables().static(k).any())


def _adjacency(problem: Problem, pairs: Iterable[int]) -> Adjacency:
    """:data:`Adjacency` of the neighbour pairs ``pairs`` (indices into ``problem.pairs``)."""
    adj: Adjacency = [[] for _ in range(problem.n)]
    for k in pairs:
        a, b = (int(x) for x in problem.pairs[k])
        adj[a].append((k, b, 0))
        adj[b].append((k, a, 1))
    return adj


def pair_graph(problem: Problem) -> Adjacency:
    """``adj[p] = [(k, q, side), …]`` over every neighbour pair (:attr:`Problem.pairs`):
    the pairs that could collide at all, whether or not their tables block a move."""
    cache = problem.__dict__.get("_pair_adj")
    if cache is None:
        cache = problem.__dict__["_pair_adj"] = _adjacency(problem, range(len(problem.pairs)))
    return cache


def conflict_graph(problem: Problem) -> Adjacency:
    """``adj[p] = [(k, q, side), …]``: the neighbour pairs ``k = (p, q)`` whose tables block
    something (pairs that can ever collide given the motion ranges); ``side`` is ``p``'s.
    With lazy tables (:attr:`CollisionTables.lazy`) every neighbour pair: proving that a
    pair never blocks would take its whole tables, and a pair that never blocks only costs
    guards that are always true."""
    cache = problem.__dict__.get("_conflict_adj")
    if cache is None and problem.tables().lazy:
        cache = problem.__dict__["_conflict_adj"] = pair_graph(problem)
        _entry_cache(problem), _successors(problem)  # held now, so that copies of the problem share them
    if cache is None:
        if problem.robot_kinematics is not None or problem.unary():  # few shared tables: many pairs per call
            problem.tables().prepare(range(len(problem.pairs)))
        blocking = [k for k in range(len(problem.pairs)) if _move_blocked_any(problem, k)]
        release_free_heap()  # the blocked tables' temporaries
        cache = problem.__dict__["_conflict_adj"] = _adjacency(problem, blocking)
    return cache


def successor_table(kin: Kinematics, deltas: Sequence[np.ndarray]) -> np.ndarray:
    """``nxt[u, i]``: the flat position after every joint moves by ``deltas[u]`` from
    position ``i`` (wrapping joints wrap), −1 past a hard stop."""
    pos = kin.all_positions()
    nxt = np.full((len(deltas), len(pos)), -1, dtype=np.int64)
    for u, d in enumerate(deltas):
        q = kin.wrap(pos + d)
        ok = kin.in_range(q)
        nxt[u, ok] = kin.flat_index(q[ok])
    return nxt


def var_names(problem: Problem, p: int) -> list[str]:
    """The finite-domain variables of positioner ``p``, one per joint."""
    if problem.kinematics.kind == "rotary":
        return [f"q{p}"]
    return [f"a{p}", f"b{p}"]


def table_bdd(ctx: Context, table: np.ndarray, names: Sequence[str]) -> BDD:
    """The BDD of a Boolean table indexed by the values of the finite-domain variables
    ``names`` (``table.shape[i] ≤ size of names[i]``; codes outside are FALSE).

    Bottom-up over the bits in the manager's level order: at each level the distinct
    (low, high) pairs of sub-functions become one ``ite`` each, so the cost is the size
    of the result, not of the table.  A large table is first cut in two at the middle
    bit: the lower half's levels are reduced once per *distinct* row of the upper half
    (a pair guard's rows are the neighbour's blocked positions, one per position of the
    mover: at 36 × 19 positions about a third of the padded codes, and rows repeat)."""
    shape = []
    for n in names:
        shape.append(1 << ctx.vars[n].width)
    full = np.zeros(shape, dtype=bool)
    full[tuple(slice(0, s) for s in table.shape)] = table
    bits = ctx.bits(names)
    t = full.reshape((2,) * len(bits))  # axis i = bits[i] (MSB first per variable)
    levels = [ctx.bdd.level_of_var(b) for b in bits]
    perm = list(np.argsort(levels))  # top level first
    t = np.transpose(t, perm).reshape(-1)
    ordered = [bits[i] for i in perm]
    nodes: list[BDD] = [ctx.false, ctx.true]
    low = len(ordered) // 2
    if len(ordered) < ROW_SPLIT_BITS:
        return nodes[int(_reduce(ctx, t.astype(np.int64), ordered, nodes)[0])]
    packed = np.ascontiguousarray(np.packbits(t.reshape(-1, 1 << low), axis=1))
    rows, inverse = np.unique(packed.view(np.dtype((np.void, packed.shape[1]))).reshape(-1), return_inverse=True)
    rows = rows.view(np.uint8).reshape(len(rows), packed.shape[1])
    distinct = np.unpackbits(rows, axis=1, count=1 << low).reshape(-1).astype(np.int64)
    row_ids = _reduce(ctx, distinct, ordered[len(ordered) - low:], nodes)  # one node per distinct row
    return nodes[int(_reduce(ctx, row_ids[inverse.reshape(-1)], ordered[:len(ordered) - low], nodes)[0])]


#: tables of at least this many bits are reduced row by row (:func:`table_bdd`)
ROW_SPLIT_BITS = 12


def _reduce(ctx: Context, ids: np.ndarray, bits: Sequence[str], nodes: list[BDD]) -> np.ndarray:
    """Reduce the node ids ``ids`` (``nodes`` indices, the last axis of ``bits`` fastest) over
    ``bits``, bottom-up: one id per block of ``2^len(bits)`` entries."""
    for b in reversed(bits):  # bottom-up: the last bit is the lowest level
        pairs = ids.reshape(-1, 2)
        base = len(nodes)
        keys = pairs[:, 0] * base + pairs[:, 1]  # one integer per (low, high)
        if base * base <= max(1 << 16, 4 * len(keys)):  # few keys possible: mark them (no sort)
            present = np.zeros(base * base, dtype=bool)
            present[keys] = True
            uniq = np.flatnonzero(present)
            inverse = (np.cumsum(present) - 1)[keys]
        else:
            uniq, inverse = np.unique(keys, return_inverse=True)
        v = ctx.bdd.var(b)
        new_ids = []
        for key in uniq.tolist():
            lo, hi = divmod(key, base)
            if lo == hi:
                new_ids.append(lo)
            else:
                nodes.append(ctx.bdd.ite(v, nodes[hi], nodes[lo]))
                new_ids.append(len(nodes) - 1)
        ids = np.asarray(new_ids, dtype=np.int64)[inverse.reshape(-1)]
    return ids
