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

from typing import Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..bdd.context import BDD, Context
from ..geometry.kinematics import Kinematics
from ..geometry.table_index import Flags, Indices, MoveIndex, Mover, Pair, Position
from ..geometry.table_store import PackedTables, release_free_heap
from ..problems.problem import Problem
from .caches import ENTRY_CACHE, Adjacency, BlockedEntryCache, caches_for

__all__ = ["blocked_table", "blocked_bits", "blocked_column", "blocked_entries", "blocked_entry", "blocked_lookup",
           "BlockedLookup", "conflict_graph", "pair_graph", "successor_table", "table_bdd", "var_names"]


def _key(problem: Problem, pair: Pair, mover: Mover) -> tuple:
    """The store key of pair ``pair``'s blocked table with mover ``mover`` (shared by equal geometry)."""
    return problem.pair_geometry_key(pair) + (mover,)


def blocked_table(problem: Problem, pair: Pair, mover: Mover) -> Flags:
    """``B[move, mover_at, other_at]``: the move ``move`` of the pair's member ``mover`` from
    ``mover_at`` is blocked while the other stands at ``other_at`` (module docstring).

    Oriented mover first, symmetrised with the reverse move from the end pose.  Shared, like
    the swept tables, by the pairs of equal geometry (:meth:`Problem.pair_geometry_key`): one
    table per offset on a grid of identical robots, not one per pair.  Kept bit-packed in the
    problem's :class:`~supcoord.planning.caches.PlanningCache`; the readers of single entries
    or columns use :func:`blocked_entry` and :func:`blocked_column`, which read the bits
    without unpacking.

    Parameters
    ----------
    problem : Problem
        The problem.
    pair : Pair
        The neighbour pair (index into ``problem.pairs``).
    mover : Mover
        The member moving (0: ``a``, 1: ``b``).

    Returns
    -------
    Flags
        Read-only ``(moves, positions, positions)`` Booleans (flat positions).

    Examples
    --------
    >>> from supcoord.problems.presets import preset_problem
    >>> problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5)
    >>> b = blocked_table(problem, 0, Mover.A)
    >>> b.shape == (len(problem.kinematics.moves()), problem.kinematics.n_positions, problem.kinematics.n_positions)
    True
    """
    store = caches_for(problem).blocked
    key = _key(problem, pair, mover)
    if key in store:
        return store.get(key)
    w = problem.tables().swept(pair, mover)
    if mover == 1:
        w = np.swapaxes(w, 1, 2)  # [move, mover_at, other_at]
    nxt, rev = _successors(problem)
    out = w.copy()
    m, at = np.nonzero(nxt >= 0)  # the moves inside the hard stops
    out[m, at] |= w[rev[m], nxt[m, at]]  # the way back must be free too
    return store.put(key, out)


def _stored(problem: Problem, pair: Pair, mover: Mover) -> tuple[PackedTables, tuple]:
    """The store and key of :func:`blocked_table` ``(pair, mover)``, the table computed if new."""
    store = caches_for(problem).blocked
    key = _key(problem, pair, mover)
    if key not in store:
        blocked_table(problem, pair, mover)
    return store, key


def blocked_bits(problem: Problem, pair: Pair, mover: Mover) -> NDArray[np.uint8]:
    """:func:`blocked_table` bit-packed on its last axis (:meth:`PackedTables.packed`).

    Parameters
    ----------
    problem : Problem
        The problem.
    pair : Pair
        The neighbour pair (index into ``problem.pairs``).
    mover : Mover
        The member moving (0: ``a``, 1: ``b``).

    Returns
    -------
    numpy.ndarray of uint8
        Read-only; ``B[move, mover_at, other_at]`` is bit ``7 − other_at % 8`` of byte
        ``[move, mover_at, other_at // 8]``.
    """
    store, key = _stored(problem, pair, mover)
    return store.packed(key)


def _lazy(problem: Problem, pair: Pair, mover: Mover) -> bool:
    """Are the pair's tables lazy (:attr:`CollisionTables.lazy`) and its blocked table not built?"""
    return problem.tables().lazy and _key(problem, pair, mover) not in caches_for(problem).blocked


def blocked_entry(problem: Problem, pair: Pair, mover: Mover, move: MoveIndex, mover_at: Position,
                  other_at: Position) -> bool:
    """``B[move, mover_at, other_at]`` of :func:`blocked_table`, read from the bits (lazy
    tables: decided on its own and remembered, :func:`blocked_entries`).

    Parameters
    ----------
    problem : Problem
        The problem.
    pair : Pair
        The neighbour pair (index into ``problem.pairs``).
    mover : Mover
        The member moving (0: ``a``, 1: ``b``).
    move : MoveIndex
        The move (index into ``problem.kinematics.moves()``).
    mover_at, other_at : Position
        Flat positions of the mover and of the other, standing.

    Returns
    -------
    bool
        True: the move is blocked.

    Examples
    --------
    >>> from supcoord.problems.presets import preset_problem
    >>> problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5)
    >>> blocked_entry(problem, 0, Mover.A, 0, 3, 5) == bool(blocked_table(problem, 0, Mover.A)[0, 3, 5])
    True
    """
    if _lazy(problem, pair, mover):
        return bool(blocked_entries(problem, pair, mover, move, mover_at, other_at)[0])
    store, key = _stored(problem, pair, mover)
    return store.bit(key, move, mover_at, other_at)


def blocked_column(problem: Problem, pair: Pair, mover: Mover, move: MoveIndex, other_at: Position) -> Flags:
    """``B[move, :, other_at]`` of :func:`blocked_table`: the mover's positions from which
    ``move`` is blocked by the other standing at ``other_at``; read from the bits (lazy
    tables: from two lines of the swept table, :meth:`CollisionTables.swept_line`).

    Parameters
    ----------
    problem : Problem
        The problem.
    pair : Pair
        The neighbour pair (index into ``problem.pairs``).
    mover : Mover
        The member moving (0: ``a``, 1: ``b``).
    move : MoveIndex
        The move (index into ``problem.kinematics.moves()``).
    other_at : Position
        Flat position of the other member, standing.

    Returns
    -------
    Flags
        One Boolean per flat position of the mover (True: blocked from there).
    """
    if _lazy(problem, pair, mover):
        tables, kin = problem.tables(), problem.kinematics
        joint, delta = kin.moves()[move]
        rev = kin.moves().index((joint, -delta))
        line = (lambda mv: tables.swept_line(pair, 0, mv, at_b=other_at)) if mover == 0 else \
            (lambda mv: tables.swept_line(pair, 1, mv, at_a=other_at))
        out = line(move).copy()
        nxt, ok = kin.step_array(kin.all_positions(), joint, delta)
        idx = np.nonzero(ok)[0]
        out[idx] |= line(rev)[kin.flat_index(nxt[idx])]
        return out
    store, key = _stored(problem, pair, mover)
    return store.column(key, move, other_at)


def _entry_cache(problem: Problem) -> BlockedEntryCache:
    cache = caches_for(problem)
    if cache.entries is None:
        kin = problem.kinematics
        cache.entries = BlockedEntryCache(kin.n_positions, len(kin.moves()))
    return cache.entries


def blocked_entries(problem: Problem, pair: ArrayLike, mover: ArrayLike, move: ArrayLike, mover_at: ArrayLike,
                    other_at: ArrayLike) -> Flags:
    """``B[move[e], mover_at[e], other_at[e]]`` of :func:`blocked_table` ``(pair[e], mover[e])``
    for every entry ``e`` (the index arrays broadcast): what the readers of lazy tables use.

    The entries remembered in the problem's cache are read; the others are decided at once
    from the swept entries of any pairs (:meth:`CollisionTables.swept_entries`): the entry,
    then (unless it is blocked already) the way back from the end pose, and remembered.

    Parameters
    ----------
    problem : Problem
        The problem.
    pair, mover, move, mover_at, other_at : array_like of int
        Per entry: the neighbour pair, the member moving (0: ``a``, 1: ``b``), the move
        (index into ``kinematics.moves()``), the flat positions of the mover and of the other.

    Returns
    -------
    Flags
        One Boolean per entry (True: blocked), flattened.

    Examples
    --------
    >>> from supcoord.problems.presets import preset_problem
    >>> problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5)
    >>> b = blocked_table(problem, 0, Mover.B)
    >>> got = blocked_entries(problem, [0, 0], Mover.B, [0, 1], [3, 4], [5, 6])
    >>> got.tolist() == [bool(b[0, 3, 5]), bool(b[1, 4, 6])]
    True
    """
    k, side, m, i, j = (np.asarray(v, dtype=np.int64).ravel() for v in np.broadcast_arrays(pair, mover, move,
                                                                                           mover_at, other_at))
    held = _entry_cache(problem)
    hits, code, n_pos = held.hits, held.code, held.n_pos
    keys = [code(problem, kk, s) + (mv * n_pos + x) * n_pos + y
            for kk, s, mv, x, y in zip(k.tolist(), side.tolist(), m.tolist(), i.tolist(), j.tolist())]
    out = np.empty(len(keys), dtype=bool)
    todo = []
    for n, key in enumerate(keys):
        hit = hits.get(key)
        if hit is None:
            todo.append(n)
        else:
            out[n] = hit
    if todo:
        sel = np.asarray(todo, dtype=np.int64)
        got = out[sel] = _decide(problem, k[sel], side[sel], m[sel], i[sel], j[sel])
        if len(hits) + len(todo) > ENTRY_CACHE:
            hits.clear()
        hits.update(zip((keys[n] for n in todo), got.tolist()))
    return out


def _decide(problem: Problem, k: Indices, side: Indices, m: Indices, i: Indices, j: Indices) -> Flags:
    """:func:`blocked_entries` decided from the swept entries, none remembered."""
    tables = problem.tables()
    nxt, rev = _successors(problem)

    def swept(sel: Indices, mv: Indices, mover_at: Indices) -> Flags:
        on_b = side[sel] == 1
        return tables.swept_entries(k[sel], side[sel], mv, np.where(on_b, j[sel], mover_at),
                                    np.where(on_b, mover_at, j[sel]))

    got = swept(np.arange(len(k)), m, i)
    back = np.nonzero(~got & (nxt[m, i] >= 0))[0]  # the way back must be free too
    if len(back):
        got[back] = swept(back, rev[m[back]], nxt[m[back], i[back]])
    return got


def _successors(problem: Problem) -> tuple[Indices, Indices]:
    """``(nxt, rev)``: ``nxt[move, at]`` the flat position after ``move`` from ``at`` (−1 past a
    hard stop), ``rev[move]`` the move back."""
    cache = caches_for(problem)
    if cache.successors is None:
        kin = problem.kinematics
        moves = kin.moves()
        pos = kin.all_positions()
        nxt = np.full((len(moves), len(pos)), -1, dtype=np.int64)
        for mv, (joint, delta) in enumerate(moves):
            q, ok = kin.step_array(pos, joint, delta)
            nxt[mv, ok] = kin.flat_index(q[ok])
        rev = np.array([moves.index((joint, -delta)) for joint, delta in moves])
        cache.successors = (nxt, rev)
    return cache.successors


class BlockedLookup(Protocol):
    """:func:`blocked_lookup`'s reader: the remembered entry, or None if not decided yet."""

    def __call__(self, pair: Pair, mover: Mover, move: MoveIndex, mover_at: Position,
                 other_at: Position) -> bool | None: ...


def blocked_lookup(problem: Problem) -> BlockedLookup:
    """The reader of the entries :func:`blocked_entries` remembered: a reader's fast path, no arrays.

    Parameters
    ----------
    problem : Problem
        The problem.

    Returns
    -------
    BlockedLookup
        ``lookup(pair, mover, move, mover_at, other_at)``: the remembered entry, None if it
        is not decided yet.
    """
    held = _entry_cache(problem)
    cache, code, n_pos = held.hits, held.code, held.n_pos
    return lambda pair, mover, move, mover_at, other_at: cache.get(code(problem, pair, mover)
                                                                   + (move * n_pos + mover_at) * n_pos + other_at)


def _move_blocked_any(problem: Problem, k: Pair, valid: Sequence[np.ndarray]) -> bool:
    """Can pair ``k`` ever block a move (a collision within the motion ranges)?  ``valid[m]``:
    the positions from which move ``m`` stays within the joints' ranges."""
    for mover in Mover:
        b = blocked_table(problem, k, mover)
        for m, ok in enumerate(valid):
            if b[m, ok].any():
                return True
    return bool(problem.tables().static(k).any())


def _blocking_pairs(problem: Problem) -> list[int]:
    """The pairs for which :func:`_move_blocked_any` holds, decided once per pair geometry
    (:meth:`Problem.pair_geometry_key`: the tables it reads are shared by equal keys)."""
    kin = problem.kinematics
    pos = kin.all_positions()
    valid = [kin.step_valid(pos, joint, delta) for joint, delta in kin.moves()]
    by_geometry: dict[tuple, bool] = {}
    out = []
    for k in range(len(problem.pairs)):
        key = problem.pair_geometry_key(k)
        hit = by_geometry.get(key)
        if hit is None:
            hit = by_geometry[key] = _move_blocked_any(problem, k, valid)
        if hit:
            out.append(k)
    return out


def _adjacency(problem: Problem, pairs: Iterable[int]) -> Adjacency:
    """:data:`Adjacency` of the neighbour pairs ``pairs`` (indices into ``problem.pairs``)."""
    adj: Adjacency = [[] for _ in range(problem.n)]
    for k in pairs:
        a, b = (int(x) for x in problem.pairs[k])
        adj[a].append((k, b, 0))
        adj[b].append((k, a, 1))
    return adj


def pair_graph(problem: Problem) -> Adjacency:
    """``adj[p] = [(k, q, mover), …]`` over every neighbour pair (:attr:`Problem.pairs`):
    the pairs that could collide at all, whether or not their tables block a move."""
    cache = caches_for(problem)
    if cache.pair_graph is None:
        cache.pair_graph = _adjacency(problem, range(len(problem.pairs)))
    return cache.pair_graph


def conflict_graph(problem: Problem) -> Adjacency:
    """``adj[p] = [(k, q, mover), …]``: the neighbour pairs ``k = (p, q)`` whose tables block
    something (pairs that can ever collide given the motion ranges); ``mover`` is ``p``'s
    member of the pair.  With lazy tables (:attr:`CollisionTables.lazy`) every neighbour
    pair: proving that a pair never blocks would take its whole tables, and a pair that
    never blocks only costs guards that are always true."""
    cache = caches_for(problem)
    if cache.conflict_graph is None and problem.tables().lazy:
        cache.conflict_graph = pair_graph(problem)
    if cache.conflict_graph is None:
        if problem.robot_kinematics is not None or problem.unary():  # few shared tables: many pairs per call
            problem.tables().prepare(range(len(problem.pairs)))
        blocking = _blocking_pairs(problem)
        release_free_heap()  # the blocked tables' temporaries
        cache.conflict_graph = _adjacency(problem, blocking)
    return cache.conflict_graph


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
