"""Collision geometry and tables (numpy, vectorised over pairs and positions).

Positioners ``a`` and ``b`` with colliding segments ``S_a(q_a)``, ``S_b(q_b)`` and
buffers ``r_a``, ``r_b`` *collide* when ``dist(S_a, S_b) < r_a + r_b``.

- Neighbour pairs: ``{(a, b) : a < b, |x_a − x_b| < reach_a + reach_b + r_a + r_b}``
  (only these can ever collide; :mod:`.pairs`).
- Static table of a pair: ``T[i, j] = dist(S_a(i), S_b(j)) < r_a + r_b`` over all
  positions ``i`` of ``a`` and ``j`` of ``b``.
- Swept table for a one-step move ``m = (joint, δ)`` of the mover while the other stands
  at ``j``: ``W_m[i, j] = ∃t ∈ [0, 1]. dist(S_mover(i + t·δ·e_joint), S_other(j)) < r_a + r_b``.

*Collides* means ``dist < r_a + r_b`` (strictly; touching at exactly ``r_a + r_b`` is
free) — the one definition shared with the validator (:mod:`supcoord.problems.validate`).

Swept tables are **exact**: a single-joint move turns the colliding segment rigidly about
a fixed centre (:meth:`Kinematics.rotation`), and the least distance over the turn has a
closed form (:func:`.sweep.rotation_clearance`), so every entry ``W_m[i, j]`` is decided
with no tolerance (to floating-point rounding).  The verdicts and certificates of the
planner rest only on these tables and the static ones.

Motions of several joints at once (both positioners of a pair, or two joints of one: the
schedules and the simultaneous semantics, never a verdict) are checked by certified
sampling, conservative by at most ``tol`` (default 1e-6 mm): :mod:`.motion`.

Distances between segments are those of :mod:`.segments` (re-exported here).

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.9 (segments).
- C. Sayres et al., kaiju (SDSS-V): collision buffer around the beta arm.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .kinematics import Kinematics
from .batch import KinematicsArrays, batch_swept
from .entries import LazyDistances, SweptEntries
from .fleet import intern_kinematics, robot_reaches, robot_segments, robots_motion_collides
from .motion import DEFAULT_TOL, motion_collides, placed_segments, prefiltered_motion_collides, turn_collides
from .pair_tables import MAX_TABLE_ENTRIES, distance_table, simultaneous_table, static_table, swept_table
from .pairs import colliding_pairs, neighbour_pairs
from .segments import point_segment_distance, segment_distance
from .sweep import rotation_clearance
from .table_index import Flags, MoveIndex, Mover, Pair, Position
from .table_store import PackedTables, RecentArrays, release_free_heap

__all__ = ["segment_distance", "point_segment_distance", "rotation_clearance", "neighbour_pairs", "turn_collides",
           "placed_segments", "static_table", "swept_table", "motion_collides", "distance_table", "simultaneous_table",
           "prefiltered_motion_collides", "colliding_pairs", "robots_motion_collides", "robot_segments", "robot_reaches",
           "intern_kinematics", "CollisionTables", "TableStatistics", "DEFAULT_TOL", "MAX_TABLE_ENTRIES"]

#: bytes of float distance tables kept (least recently used dropped, recomputed on demand)
DIST_CACHE_BYTES = 512 * 2**20
#: bytes of static and swept tables kept unpacked (all are kept bit-packed)
UNPACKED_CACHE_BYTES = 256 * 2**20
#: above this many bytes of bit-packed swept tables (every distinct pair, both movers), the
#: tables are *lazy*: entries and lines are decided one by one as the planner reads them,
#: and a whole table is built only for a pair that a window encodes (:class:`CollisionTables`).
#: Measured on the APO wok (``benchmarks/results/instrument_lazy.md``, ``solve(improve=0)``):
#: lazy tables took 0.5x the time at 19 x 10 (134 MB of tables), 0.43x at 25 x 13, 0.21x at
#: 37 x 19, and as long at 13 x 7 (31 MB), with 1/3 to 1/8 of the memory and the same plans
LAZY_TABLE_BYTES = 64 * 2**20
#: bytes of lazy lines (a swept table's ``[m, i, :]`` or ``[m, :, j]``) kept
LINE_CACHE_BYTES = 128 * 2**20


@dataclass(frozen=True)
class TableStatistics:
    """What :meth:`CollisionTables.statistics` reports: ``positioners``, ``pairs`` (neighbour
    pairs), ``distinct_offsets`` (pairs of distinct geometry, the tables computed),
    ``colliding_fraction`` (mean fraction of colliding position pairs of the static tables,
    in [0, 1], weighted by pairs) and ``positions`` (positions of one positioner)."""

    positioners: int
    pairs: int
    distinct_offsets: int
    colliding_fraction: float
    positions: int


class CollisionTables:
    """Static and swept tables of every neighbour pair of one layout, computed on demand.

    Pairs of identical robots (equal :meth:`Kinematics.key`) with the same offset
    ``x_b − x_a`` and buffer sum share their tables (a hex grid of identical robots has only
    a handful of distinct offsets), so a grid of hundreds of positioners costs a few table
    computations; robots with their own lattices or arms (``kins``, one per robot) have
    their own.  ``pairs[pair] = (a, b)``; ``static(pair)[at_a, at_b]`` and
    ``swept(pair, mover)[move, at_a, at_b]`` index positions of ``a`` by ``at_a`` and of ``b``
    by ``at_b`` whoever moves (the names of :mod:`.table_index`); :meth:`swept_entry`,
    :meth:`swept_line` and :meth:`swept_entries` read one entry, one line or many entries of
    any pairs.

    ``unary[p] = (U, V)`` (:mod:`.obstacles`: fixed obstacles, robots held in place) is folded
    into every table of ``p``'s pairs: ``T ∨ U_a[i] ∨ U_b[j]``, a move ``m`` of ``a`` blocked
    where ``V_a[m, i] ∨ U_b[j]`` (and likewise for ``b``), so whoever reads the tables
    honours them.  Such robots have tables of their own.

    **Lazy tables.**  Where the distinct tables would hold more than
    :data:`LAZY_TABLE_BYTES` bit-packed (``lazy=None``: decided from the sizes; the real APO
    wok at 37 × 19 positions, 3,713 distinct pairs, would hold 1.8 GB, at 73 × 37 27 GB),
    nothing is tabulated ahead: :meth:`swept_entry` and :meth:`swept_line` decide the entries
    they are asked for (:meth:`swept_entries`, the same end-point prefilter and exact closed
    form as :func:`swept_table` on the same numbers, so the same Booleans), and
    :meth:`swept` builds a whole table only for a pair that is asked for one.
    """

    def __init__(self, kin: Kinematics, bases: Any, buffers: Any, tol: float = DEFAULT_TOL,
                 kins: list[Kinematics] | None = None, unary: dict[int, tuple[np.ndarray, np.ndarray]] | None = None,
                 lazy: bool | None = None):
        self.kin = kin
        self.bases = np.asarray(bases, float)
        self.buffers = np.broadcast_to(np.asarray(buffers, float), (len(self.bases),)).copy()
        self.tol = tol
        self._distinct, self._ids = intern_kinematics(kins, len(self.bases))
        self.unary = dict(unary or {})
        self._own: dict[int, Kinematics] = {}  # table ids of robots with unary tables
        if self.unary:
            first = int(self._ids.max(initial=-1)) + 1
            for p in sorted(self.unary):
                self._own[first + p] = kin if kins is None else kins[p]
                self._ids[p] = first + p
        self.pairs = neighbour_pairs(self.bases, robot_reaches(kins if kins is not None else kin, len(self.bases)),
                                     self.buffers)
        self._keys: dict[int, tuple] = {}  # pair -> its sharing key (offset, buffer sum, kinematics ids)
        # static tables by _key(k), swept ones by _key(k) + (mover,): one bit an entry (table_store)
        self._bits = PackedTables(UNPACKED_CACHE_BYTES)
        self._simultaneous: dict[tuple, np.ndarray] = {}
        self._dist = RecentArrays(DIST_CACHE_BYTES)
        self._lines = RecentArrays(LINE_CACHE_BYTES)  # lazy: (swept key, m, axis, index) -> line
        self._decider: SweptEntries | None = None  # lazy: the stacked geometry of every pair
        self.lazy = self.table_bytes() > LAZY_TABLE_BYTES if lazy is None else bool(lazy)

    def table_bytes(self) -> int:
        """Bytes of the bit-packed swept tables of every distinct pair (both movers), were they
        all computed: what decides :attr:`lazy`."""
        total = 0
        for key in set(self._key(k) for k in range(len(self.pairs))):
            ka, kb = self._kin(key[2]), self._kin(key[3])
            total += len(ka.moves()) * ka.n_positions * ((kb.n_positions + 7) // 8)
            total += len(kb.moves()) * kb.n_positions * ((ka.n_positions + 7) // 8)
        return total

    def _kin(self, u: int) -> Kinematics:
        if u in self._own:
            return self._own[u]
        return self.kin if self._distinct is None else self._distinct[u]

    def _unary(self, k: int) -> tuple[tuple | None, tuple | None]:
        a, b = (int(v) for v in self.pairs[k])
        return self.unary.get(a), self.unary.get(b)

    def geometry_key(self, a: int, b: int) -> tuple[float, float, float, int, int]:
        """What the collision geometry of robots ``a`` and ``b`` depends on: ``(offset x, offset y,
        buffer sum, table id of a, table id of b)``, offset ``x_b − x_a`` in mm rounded to 1e-9.
        Robots with equal table ids have the same kinematics and no unary tables of their own,
        so equal keys mean equal tables (what the tables share by)."""
        off = np.round(self.bases[b] - self.bases[a], 9) + 0.0
        return (float(off[0]), float(off[1]), round(float(self.buffers[a] + self.buffers[b]), 9),
                int(self._ids[a]), int(self._ids[b]))

    def _key(self, k: int) -> tuple:
        key = self._keys.get(k)
        if key is None:
            a, b = self.pairs[k]
            off = np.round(self.bases[b] - self.bases[a], 9) + 0.0
            key = self._keys[k] = ((float(off[0]), float(off[1])), round(float(self.buffers[a] + self.buffers[b]), 9),
                                   int(self._ids[a]), int(self._ids[b]))
        return key

    def static(self, k: int) -> np.ndarray:
        key = self._key(k)
        if key not in self._bits:
            off, _, ua, ub = key
            return self._keep_static(k, self._distances(off, ua, ub) < key[1])
        return self._bits.get(key)

    def _keep_static(self, k: int, table: np.ndarray) -> np.ndarray:
        """Store pair ``k``'s static table ``D < r_a + r_b`` with the unary tables folded in."""
        key = self._key(k)
        fa, fb = self._unary(k)
        if fa is not None:
            table = table | fa[0][:, None]
        if fb is not None:
            table = table | fb[0][None, :]
        return self._bits.put(key, table)

    def distances(self, k: int) -> np.ndarray:
        """``D[i, j]``: the distance between pair ``k``'s colliding segments, ``a`` at position
        ``i`` and ``b`` at ``j`` (:func:`distance_table`; shared like the tables)."""
        off, _, ua, ub = self._key(k)
        return self._distances(off, ua, ub)

    def _distances(self, offset: tuple[float, float], ua: int = 0, ub: int = 0) -> np.ndarray:
        key = (offset, ua, ub)
        out = self._dist.get(key)
        if out is None:
            neg = self._dist.get(((-offset[0] + 0.0, -offset[1] + 0.0), ub, ua))
            if neg is not None:  # D_{-o}[j, i] = D_o[i, j]
                return neg.T
            out = self._dist.put(key, distance_table(self._kin(ua), (0.0, 0.0), offset, self._kin(ub)))
        return out

    @staticmethod
    def _mirror_key(key: tuple) -> tuple:
        """The key of the same swept table seen from the other robot: ``b`` moving past ``a`` at
        offset ``o`` is ``a`` moving past ``b`` at ``−o``, stored transposed."""
        (ox, oy), bsum, ua, ub, mover = key
        return ((-ox + 0.0, -oy + 0.0), bsum, ub, ua, 1 - mover)

    def swept(self, pair: Pair, mover: Mover) -> Flags:
        """``W[move, at_a, at_b]``: the move ``move`` of the pair's member ``mover`` collides with
        the other standing, ``a`` at ``at_a`` and ``b`` at ``at_b`` (:func:`swept_table`, the
        unary tables folded in).  The whole table, built if it is not stored; read-only."""
        key = self._key(pair) + (mover,)
        if key not in self._bits:
            (ox, oy), bsum, ua, ub = key[:4]
            mirror = self._mirror_key(key)
            if mirror in self._bits:  # b moving past a at offset o is a moving past b at −o
                return np.swapaxes(self._bits.get(mirror), 1, 2)
            table = swept_table(self._kin(ua), (0.0, 0.0), (ox, oy), bsum, mover, kin_b=self._kin(ub),
                                distances=self._distances((ox, oy), ua, ub))
            return self._bits.put(key, self._fold_swept(pair, mover, table))
        return self._bits.get(key)

    def _swept_key(self, pair: Pair, mover: Mover) -> tuple[tuple, bool]:
        """The stored key of ``swept(pair, mover)`` and whether it is stored transposed (mirror)."""
        key = self._key(pair) + (mover,)
        if key not in self._bits:
            mirror = self._mirror_key(key)
            if mirror in self._bits:
                return mirror, True
            self.swept(pair, mover)
        return key, False

    def _stored_swept(self, pair: Pair, mover: Mover) -> tuple[tuple, bool] | None:
        """``(key, mirrored)`` of ``swept(pair, mover)`` if it is stored (itself or its mirror), else None."""
        key = self._key(pair) + (mover,)
        if key in self._bits:
            return key, False
        mirror = self._mirror_key(key)
        return (mirror, True) if mirror in self._bits else None

    def swept_entry(self, pair: Pair, mover: Mover, move: MoveIndex, at_a: Position, at_b: Position) -> bool:
        """``swept(pair, mover)[move, at_a, at_b]``, read from the bits (no table unpacked); a
        lazy table's entry is decided on its own (:meth:`swept_entries`) unless the table is stored.

        Parameters
        ----------
        pair : Pair
            The neighbour pair (index into :attr:`pairs`).
        mover : Mover
            The member moving (0: ``a``, 1: ``b``).
        move : MoveIndex
            The move (index into the mover's ``moves()``).
        at_a, at_b : Position
            Flat positions of ``a`` and of ``b``.

        Returns
        -------
        bool
            True: the move collides.
        """
        if self.lazy and self._stored_swept(pair, mover) is None:
            return bool(self._decide_entries(pair, mover, move, at_a, at_b)[0])
        key, mirrored = self._swept_key(pair, mover)
        return self._bits.bit(key, move, at_b, at_a) if mirrored else self._bits.bit(key, move, at_a, at_b)

    def swept_line(self, pair: Pair, mover: Mover, move: MoveIndex, *, at_a: Position | None = None,
                   at_b: Position | None = None) -> Flags:
        """``swept(pair, mover)[move, at_a, :]`` (given ``at_a``) or ``[move, :, at_b]`` (given
        ``at_b``), from the bits (a lazy table's line decided on its own, :meth:`swept_entries`,
        and kept while recent).

        Raises
        ------
        InputError
            Unless exactly one of ``at_a`` and ``at_b`` is given.
        """
        if (at_a is None) == (at_b is None):
            raise InputError("swept_line takes exactly one of at_a and at_b", value=(at_a, at_b))
        if self.lazy and self._stored_swept(pair, mover) is None:
            line_key = self._key(pair) + (mover, move, at_a, at_b)
            line = self._lines.get(line_key)
            if line is None:
                _, _, ua, ub = self._key(pair)
                if at_a is not None:
                    jj = np.arange(self._kin(ub).n_positions)
                    ii = np.full(len(jj), at_a)
                else:
                    ii = np.arange(self._kin(ua).n_positions)
                    jj = np.full(len(ii), at_b)
                line = self._lines.put(line_key, self._decide_entries(pair, mover, move, ii, jj))
            return line
        key, mirrored = self._swept_key(pair, mover)
        if at_a is not None:
            return self._bits.column(key, move, at_a) if mirrored else self._bits.row(key, move, at_a)
        return self._bits.row(key, move, at_b) if mirrored else self._bits.column(key, move, at_b)

    def swept_entries(self, pair: ArrayLike, mover: ArrayLike, move: ArrayLike, at_a: ArrayLike,
                      at_b: ArrayLike) -> Flags:
        """``swept(pair[e], mover[e])[move[e], at_a[e], at_b[e]]`` for every entry ``e`` of any
        pairs (the index arrays broadcast): read from the bits, or for lazy tables decided at
        once from the geometry without the tables (:class:`.entries.SweptEntries`, the same
        Booleans as :func:`swept_table`); nothing is remembered.

        Parameters
        ----------
        pair, mover, move, at_a, at_b : array_like of int
            Per entry: the neighbour pair, the member moving (0: ``a``, 1: ``b``), the move
            (index into ``moves()``), the flat positions of ``a`` and of ``b``.

        Returns
        -------
        Flags
            One Boolean per entry (True: the move collides), flattened.
        """
        if self.lazy:
            return self._decide_entries(pair, mover, move, at_a, at_b)
        cells = np.broadcast_arrays(*(np.asarray(v, dtype=np.int64) for v in (pair, mover, move, at_a, at_b)))
        return np.array([self.swept_entry(*cell) for cell in zip(*(c.ravel().tolist() for c in cells))], dtype=bool)

    def _entries_of(self) -> SweptEntries:
        if self._decider is None:
            keys = [self._key(q) for q in range(len(self.pairs))]
            self._decider = SweptEntries(self._kin, self._ids, self.pairs, keys, self.unary)
        return self._decider

    def _decide_entries(self, pair: ArrayLike, mover: ArrayLike, move: ArrayLike, at_a: ArrayLike,
                        at_b: ArrayLike) -> Flags:
        """:meth:`swept_entries` decided from the geometry (:class:`.entries.SweptEntries`)."""
        return self._entries_of().decide(pair, mover, move, at_a, at_b)

    def static_line(self, pair: Pair, *, at_a: Position | None = None, at_b: Position | None = None) -> Flags:
        """``static(pair)[at_a, :]`` (given ``at_a``) or ``[:, at_b]`` (given ``at_b``); lazy
        tables decide the line on its own (:meth:`.entries.SweptEntries.static`, the same Booleans).

        Raises
        ------
        InputError
            Unless exactly one of ``at_a`` and ``at_b`` is given.
        """
        if (at_a is None) == (at_b is None):
            raise InputError("static_line takes exactly one of at_a and at_b", value=(at_a, at_b))
        if self.lazy and self._key(pair) not in self._bits:
            line_key = self._key(pair) + ("static", at_a, at_b)
            line = self._lines.get(line_key)
            if line is None:
                _, _, ua, ub = self._key(pair)
                idx = np.arange(self._kin(ub).n_positions if at_a is not None else self._kin(ua).n_positions)
                line = self._lines.put(line_key, self._entries_of().static(pair, at_a, idx) if at_a is not None else
                                       self._entries_of().static(pair, idx, at_b))
            return line
        return self.static(pair)[at_a, :] if at_a is not None else self.static(pair)[:, at_b]

    def distance_view(self, k: int) -> Any:
        """Pair ``k``'s :meth:`distances` as read by :func:`.motion.prefiltered_motion_collides`
        (``[ia, jb]``, ``.T``): the table, or for lazy tables a :class:`.entries.LazyDistances`."""
        if self.lazy:
            return LazyDistances(self._entries_of(), k)
        return self.distances(k)

    def _fold_swept(self, k: int, mover: int, table: np.ndarray, rows_of_mover: bool = False) -> np.ndarray:
        """``table`` (``swept(k, mover)``, or with ``rows_of_mover`` its transpose ``[m, j, i]``
        for ``mover = 1``) with the unary tables folded in (class docstring)."""
        fa, fb = self._unary(k)
        if mover == 0:
            table |= (fa[1][:, :, None] if fa is not None else False) | (fb[0][None, None, :] if fb is not None else False)
        elif rows_of_mover:
            table |= (fb[1][:, :, None] if fb is not None else False) | (fa[0][None, None, :] if fa is not None else False)
        else:
            table |= (fb[1][:, None, :] if fb is not None else False) | (fa[0][None, :, None] if fa is not None else False)
        return table

    def prepare(self, ks: Any, chunk: int = 256) -> None:
        """Compute the swept tables of pairs ``ks`` (both movers) ahead, many pairs per call
        (:func:`.batch.batch_swept`): what a layout of robots with their own geometry needs,
        where few pairs share tables.  The tables are the ones :meth:`swept` computes."""
        todo = [int(k) for k in ks if self._key(int(k)) + (0,) not in self._bits]
        arrays: dict[int, KinematicsArrays] = {}
        for lo in range(0, len(todo), chunk):
            part = todo[lo:lo + chunk]
            keys = [self._key(k) for k in part]
            for _, _, ua, ub in keys:
                for u in (ua, ub):
                    if u not in arrays:
                        arrays[u] = KinematicsArrays(self._kin(u))
            done = batch_swept([arrays[key[2]] for key in keys], [arrays[key[3]] for key in keys],
                               [key[0] for key in keys], [key[1] for key in keys])
            for k, key, (static, w0, w1) in zip(part, keys, done):
                if key not in self._bits:
                    self._keep_static(k, static)
                self._bits.put(key + (0,), self._fold_swept(k, 0, w0))
                # b moving, in b's rows: what the mirrored pair stores (a moving past b at −o)
                self._bits.put(self._mirror_key(key + (1,)), self._fold_swept(k, 1, w1, rows_of_mover=True))
            del done
            release_free_heap()  # the chunk's full tables are gone; only their bits stay

    def simultaneous(self, k: int) -> np.ndarray:
        """:func:`simultaneous_table` of pair ``k`` (``[u, v, i, j]``, ``u``/``v`` = 0 for standing)."""
        key = self._key(k) + ("sim",)
        if key not in self._simultaneous:
            (ox, oy), bsum, ua, ub = key[:4]
            mirror = ((-ox + 0.0, -oy + 0.0), bsum, ub, ua, "sim")
            if mirror in self._simultaneous:  # S_{-o}[v, u, j, i] = S_o[u, v, i, j]
                return np.transpose(self._simultaneous[mirror], (1, 0, 3, 2))
            table = simultaneous_table(self._kin(ua), (0.0, 0.0), (ox, oy), bsum, self.tol,
                                       distances=self._distances((ox, oy), ua, ub), kin_b=self._kin(ub))
            fa, fb = self._unary(k)
            if fa is not None:  # standing: U; move u: V[u − 1]
                table |= np.concatenate([fa[0][None], fa[1]])[:, None, :, None]
            if fb is not None:
                table |= np.concatenate([fb[0][None], fb[1]])[None, :, None, :]
            self._simultaneous[key] = table
        return self._simultaneous[key]

    def neighbours_of(self, p: int) -> list[tuple[int, int, int]]:
        """``(k, other, side)`` for every pair ``k`` containing ``p`` (``side`` 0 if ``p`` is ``a``)."""
        out = []
        for k, (a, b) in enumerate(self.pairs):
            if a == p:
                out.append((k, int(b), 0))
            elif b == p:
                out.append((k, int(a), 1))
        return out

    def statistics(self) -> TableStatistics:
        """Pairs, distinct offsets, and the fraction of colliding position pairs (static)."""
        keys = [self._key(k) for k in range(len(self.pairs))]
        distinct = sorted(set(keys))
        fractions = []
        for key in distinct:
            k = keys.index(key)
            fractions.append(float(self.static(k).mean()))
        weights = [keys.count(key) for key in distinct]
        mean = float(np.average(fractions, weights=weights)) if fractions else 0.0
        return TableStatistics(len(self.bases), len(self.pairs), len(distinct), mean, self.kin.n_positions)
