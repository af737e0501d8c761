"""Swept-table entries of many pairs decided at once, without their tables (lazy tables).

A fine lattice on a real focal plane has too many distinct tables to compute ahead (the APO
wok at 73 × 37 positions: 27 GB of bits), while a planner reads only a sliver of them: the
entries around the robots' current poses.  :class:`SweptEntries` decides any list of
entries ``W[m, i, j]`` of :func:`.collision.swept_table` — pair, mover, move, positions —
in one vectorised pass over all of them, whatever pair each belongs to: every distinct
kinematics' segments, successors and rotations are stacked once, and each entry gathers
its own.

Each entry is decided as the table decides it, on the same numbers: the segments placed
in the pair's frame (``a`` at the origin, ``b`` at the rounded offset), a reversed move as
its forward move from the end pose (:meth:`.Kinematics.reversed_moves`), a move past a
hard stop blocked, the end-point distances (``a``'s segment first, as
:func:`.collision.distance_table` has them) settling what they can, the exact closed form
(:func:`.sweep.rotation_clearance`) the rest, then the unary tables folded in.  So the
Booleans are the table's (``tests/geometry/test_sweep.py`` compares every entry).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from .joint_space import Kinematics
from .segments import segment_distance
from .sweep import rotation_clearance

__all__ = ["SweptEntries", "LazyDistances"]


class SweptEntries:
    """Decides swept entries of the pairs of one :class:`.collision.CollisionTables`.

    ``kin_of(u)``: the kinematics of table id ``u``; ``ids[p]``: robot ``p``'s table id;
    ``keys[k] = (offset, bsum, ua, ub)`` (the tables' sharing key of pair ``k``);
    ``pairs[k] = (a, b)``; ``unary[p] = (U, V)`` (robot ``p``'s own refusals)."""

    def __init__(self, kin_of: Callable[[int], Kinematics], ids: Any, pairs: np.ndarray, keys: list[tuple],
                 unary: dict[int, tuple[np.ndarray, np.ndarray]]):
        used = sorted(set(int(u) for u in np.asarray(ids).ravel()) | {int(key[c]) for key in keys for c in (2, 3)})
        rows: dict[int, int] = {}  # kinematics object -> its row: a robot with unary tables has its own id only
        kins: list[Kinematics] = []
        self.row = np.zeros(max(used, default=0) + 1, dtype=np.int64)  # table id -> geometry row
        for u in used:
            kin = kin_of(u)
            if id(kin) not in rows:
                rows[id(kin)] = len(kins)
                kins.append(kin)
            self.row[u] = rows[id(kin)]
        self.n_moves = max(len(k.moves()) for k in kins)
        npos = max(k.n_positions for k in kins)
        nj = kins[0].n_joints
        n = len(kins)
        self.seg = np.zeros((n, npos, 2, 2))
        self.nxt = np.full((n, self.n_moves, npos), -1, dtype=np.int32)  # −1: past a hard stop
        self.centre = np.zeros((n, self.n_moves, npos, 2))
        self.angle = np.zeros((n, self.n_moves, npos))
        self.length = np.zeros((n, self.n_moves))
        self.forward = np.arange(self.n_moves)  # move -> its forward move (itself unless reversed)
        self.reversed = np.zeros(self.n_moves, dtype=bool)
        for u, kin in enumerate(kins):
            pos = kin.all_positions()
            self.seg[u, :len(pos)] = kin.segments(pos)
            for m, (joint, delta) in enumerate(kin.moves()):
                nxt, ok = kin.step_array(pos, joint, delta)
                self.nxt[u, m, np.nonzero(ok)[0]] = kin.flat_index(nxt[ok])
                centre, angle = kin.rotation(pos.astype(float), joint, np.full(len(pos), float(delta)))
                self.centre[u, m, :len(pos)] = centre
                self.angle[u, m, :len(pos)] = angle
                d = np.zeros(nj)
                d[joint] = delta
                self.length[u, m] = float(kin.sweep_length(d))
        for r, f in kins[0].reversed_moves().items():
            self.forward[r] = f
            self.reversed[r] = True
        self.pa = np.asarray(pairs, dtype=np.int64)[:, 0]
        self.pb = np.asarray(pairs, dtype=np.int64)[:, 1]
        self.offset = np.array([key[0] for key in keys], dtype=float).reshape(-1, 2)
        self.bsum = np.array([key[1] for key in keys], dtype=float)
        self.ua = np.array([key[2] for key in keys], dtype=np.int64)
        self.ub = np.array([key[3] for key in keys], dtype=np.int64)
        robots = sorted(unary)
        size = max(int(self.pa.max(initial=-1)), int(self.pb.max(initial=-1)), max(robots, default=-1)) + 1
        self.unary_row = np.full(size, -1, dtype=np.int64)  # robot -> its row of unary tables (−1: none)
        self.unary_row[robots] = np.arange(len(robots))
        self.u_static = np.ones((len(robots), npos), dtype=bool)
        self.u_moves = np.ones((len(robots), self.n_moves, npos), dtype=bool)
        for row, p in enumerate(robots):
            U, V = unary[p]
            self.u_static[row, :len(U)] = U
            self.u_moves[row, :V.shape[0], :V.shape[1]] = V

    def decide(self, k: Any, mover: Any, m: Any, i: Any, j: Any) -> np.ndarray:
        """``swept(k[e], mover[e])[m[e], i[e], j[e]]`` for every entry ``e`` (``i`` indexes ``a``'s
        positions, ``j`` ``b``'s, whichever moves); arrays broadcast."""
        k, mover, m, i, j = (np.asarray(v, dtype=np.int64).ravel() for v in np.broadcast_arrays(k, mover, m, i, j))
        on_b = mover == 1
        um = self.row[np.where(on_b, self.ub[k], self.ua[k])]  # geometry rows of the mover, the other
        us = self.row[np.where(on_b, self.ua[k], self.ub[k])]
        zero = np.zeros((len(k), 2))
        off = self.offset[k]
        bm = np.where(on_b[:, None], off, zero)  # the pair's frame: a at the origin, b at the offset
        bs = np.where(on_b[:, None], zero, off)
        im = np.where(on_b, j, i)  # the mover's position, the other's
        js = np.where(on_b, i, j)
        fwd = self.forward[m]
        start = np.where(self.reversed[m], self.nxt[um, m, im], im)  # W_r[i] = W_f[step_r(i)]
        end = np.where(start >= 0, self.nxt[um, fwd, np.maximum(start, 0)], -1)
        out = np.ones(len(k), dtype=bool)  # past a hard stop: blocked
        e = np.nonzero(end >= 0)[0]
        if len(e):
            s_other = self.seg[us[e], js[e]] + bs[e][:, None, :]
            s0 = self.seg[um[e], start[e]] + bm[e][:, None, :]
            s1 = self.seg[um[e], end[e]] + bm[e][:, None, :]
            b_first = on_b[e][:, None, None]
            d0, d1 = (self._distance(np.where(b_first, s_other, s), np.where(b_first, s, s_other)) for s in (s0, s1))
            bsum = self.bsum[k[e]]
            hit = (d0 < bsum) | (d1 < bsum)
            length = self.length[um[e], fwd[e]]
            open_ = np.nonzero(~hit & ~((d0 + d1 - length) / 2 >= bsum))[0]
            if len(open_):
                x = e[open_]
                centre = self.centre[um[x], fwd[x], start[x]] + bm[x]
                clearance = rotation_clearance(s0[open_], centre, self.angle[um[x], fwd[x], start[x]], s_other[open_])
                hit[open_] = clearance < bsum[open_]
            out[e] = hit
        own = self.unary_row[np.where(on_b, self.pb[k], self.pa[k])]
        other = self.unary_row[np.where(on_b, self.pa[k], self.pb[k])]
        sel = np.nonzero(own >= 0)[0]
        out[sel] |= self.u_moves[own[sel], m[sel], im[sel]]
        sel = np.nonzero(other >= 0)[0]
        out[sel] |= self.u_static[other[sel], js[sel]]
        return out

    def distance(self, k: Any, i: Any, j: Any) -> np.ndarray:
        """``distances(k[e])[i[e], j[e]]`` (:func:`.collision.distance_table` in the pair's frame,
        ``a`` at ``i``, ``b`` at ``j``) for every entry ``e``; arrays broadcast."""
        k, i, j = (np.asarray(v, dtype=np.int64) for v in np.broadcast_arrays(k, i, j))
        sa = self.seg[self.row[self.ua[k]], i] + np.zeros(2)
        sb = self.seg[self.row[self.ub[k]], j] + self.offset[k][..., None, :]
        return self._distance(sa, sb)

    def static(self, k: Any, i: Any, j: Any) -> np.ndarray:
        """``static(k[e])[i[e], j[e]]``: ``D < r_a + r_b``, with both robots' unary tables folded in."""
        k, i, j = (np.asarray(v, dtype=np.int64) for v in np.broadcast_arrays(k, i, j))
        out = self.distance(k, i, j) < self.bsum[k]
        for robot, at in ((self.pa[k], i), (self.pb[k], j)):
            row = self.unary_row[robot]
            sel = row >= 0
            out[sel] |= self.u_static[row[sel], at[sel]]
        return out

    @staticmethod
    def _distance(sa: np.ndarray, sb: np.ndarray) -> np.ndarray:
        return segment_distance(sa[..., 0, :], sa[..., 1, :], sb[..., 0, :], sb[..., 1, :])


class LazyDistances:
    """A pair's distance table read entry by entry (``view[i, j]`` with index arrays, ``view.T``):
    what :func:`.motion.prefiltered_motion_collides` reads of :func:`.collision.distance_table`,
    for lazy tables, without the table."""

    def __init__(self, entries: SweptEntries, k: int, transposed: bool = False):
        self.entries, self.k, self.transposed = entries, k, transposed

    @property
    def T(self) -> "LazyDistances":
        return LazyDistances(self.entries, self.k, not self.transposed)

    def __getitem__(self, index: tuple[Any, Any]) -> np.ndarray:
        i, j = index
        return self.entries.distance(self.k, j, i) if self.transposed else self.entries.distance(self.k, i, j)
