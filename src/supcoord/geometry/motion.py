"""Motions checked against a neighbour: exact single-joint turns, certified simultaneous motions.

A pair *collides* when ``dist(S_a, S_b) < r_a + r_b`` (strictly; :mod:`.collision`).

- :func:`turn_collides`: one positioner moves one joint, the other stands — the mover's
  colliding segment turns rigidly about a fixed centre (:meth:`Kinematics.rotation`) and
  the least distance over the turn has a closed form (:func:`.sweep.rotation_clearance`):
  exact, no tolerance.
- :func:`motion_collides`: both move, or one moves several joints (the schedules and the
  simultaneous semantics; never a verdict).  If every point of both segments moves at most
  ``L`` mm along the motion (:meth:`Kinematics.sweep_length`), ``d(t)`` is ``L``-Lipschitz,
  so over ``[t0, t1]`` it is at least ``(d(t0) + d(t1) − L·(t1 − t0))/2``: intervals whose
  bound is below ``r`` are bisected until a sample collides (a proven collision), every
  bound clears ``r`` (proven free), or an interval's ``L·(t1 − t0)/2`` is at most ``tol``
  (default 1e-6 mm): then the motion counts as colliding, which only ever leaves a motion
  out of a plan.  Single-joint entries go to :func:`turn_collides`.

References
----------
- P. Hansen, B. Jaumard, S.-H. Lu, Global optimization of univariate Lipschitz functions,
  Mathematical Programming 55, 1992 (bounds from Lipschitz constants, interval splitting).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError
from .chain import chain_segment_rows
from .kinematics import AlphaBeta, Kinematics, Rotary
from .segments import segment_coords, segment_distance_xy
from .sweep import rotation_clearance

__all__ = ["placed_segments", "turn_collides", "motion_collides", "prefiltered_motion_collides", "DEFAULT_TOL", "CHUNK"]

#: default tolerance (mm) of the certified sampling of simultaneous motions
DEFAULT_TOL = 1e-6
#: entries handled per chunk (bounds memory: ~ CHUNK × a few floats per sample)
CHUNK = 1 << 16


def placed_segments(kin: Kinematics, base: Any, q: Any) -> np.ndarray:
    """Colliding segments in the focal plane: ``kin.segments(q) + base`` (``(..., 2, 2)``)."""
    return kin.segments(q) + np.asarray(base, float)[..., None, :]


def motion_collides(kin_a: Kinematics, base_a: Any, qa: Any, da: Any,
                    kin_b: Kinematics, base_b: Any, qb: Any, db: Any,
                    bsum: Any, tol: float = DEFAULT_TOL, coarse: int = 4) -> np.ndarray:
    """Does the simultaneous motion ``q_a + t·d_a``, ``q_b + t·d_b`` (``t ∈ [0,1]``) collide?

    All position/delta arrays are ``(..., J)``, bases ``(..., 2)``, ``bsum`` ``(...)``; they
    broadcast against each other (bases may differ per entry); the result is a bool
    array over the broadcast leading shape.  Entries where one positioner moves one
    joint and the other stands are exact (:func:`turn_collides`); the others are sampled
    with the certificate of the module docstring, conservative by at most ``tol`` mm.
    """
    if not tol > 0:
        raise InputError(f"tol must be positive, got {tol!r}", value=tol)
    qa, da, qb, db = (np.asarray(v, float) for v in (qa, da, qb, db))
    bsum = np.asarray(bsum, float)
    lead = np.broadcast_shapes(qa.shape[:-1], da.shape[:-1], qb.shape[:-1], db.shape[:-1], bsum.shape,
                               np.shape(base_a)[:-1], np.shape(base_b)[:-1])
    bsum = np.broadcast_to(bsum, lead).reshape(-1)
    qa = np.broadcast_to(qa, lead + qa.shape[-1:]).reshape(-1, qa.shape[-1])
    da = np.broadcast_to(da, lead + da.shape[-1:]).reshape(-1, da.shape[-1])
    qb = np.broadcast_to(qb, lead + qb.shape[-1:]).reshape(-1, qb.shape[-1])
    db = np.broadcast_to(db, lead + db.shape[-1:]).reshape(-1, db.shape[-1])
    base_a = np.broadcast_to(np.asarray(base_a, float), lead + (2,)).reshape(-1, 2)
    base_b = np.broadcast_to(np.asarray(base_b, float), lead + (2,)).reshape(-1, 2)
    length = kin_a.sweep_length(da) + kin_b.sweep_length(db)  # (E,)
    result = np.zeros(len(qa), dtype=bool)
    moving_a, moving_b = (da != 0).sum(axis=1), (db != 0).sum(axis=1)
    exact = np.zeros(len(qa), dtype=bool)
    for side, (kin_m, kin_s, qm, dm, qs, bm, bs, n_m, n_s) in enumerate((
            (kin_a, kin_b, qa, da, qb, base_a, base_b, moving_a, moving_b),
            (kin_b, kin_a, qb, db, qa, base_b, base_a, moving_b, moving_a))):
        for joint in range(kin_m.n_joints):
            sel = np.nonzero((n_m == 1) & (n_s == 0) & (dm[:, joint] != 0))[0]
            if len(sel):
                result[sel] = turn_collides(kin_m, bm[sel], qm[sel], joint, dm[sel, joint], kin_s, bs[sel], qs[sel],
                                            bsum[sel])
                exact[sel] = True
    todo = np.nonzero(~exact)[0]
    if len(todo):
        result[todo] = _bisect_collides(kin_a, base_a[todo], qa[todo], da[todo], kin_b, base_b[todo], qb[todo],
                                        db[todo], bsum[todo], length[todo], tol, max(1, int(coarse)))
    return result.reshape(lead)


def prefiltered_motion_collides(kin_a: Kinematics, base_a: Any, pos: np.ndarray, ia: np.ndarray, ia1: np.ndarray,
                                da: Any, kin_b: Kinematics, base_b: Any, jb: np.ndarray, jb1: np.ndarray, db: Any,
                                bsum: float, distances: np.ndarray, tol: float = DEFAULT_TOL) -> np.ndarray:
    """:func:`motion_collides` of ``a`` moving ``da`` from lattice position ``ia`` (to ``ia1``)
    while ``b`` moves ``db`` from ``jb`` (to ``jb1``), entries ``(E,)``, settled first by the
    end-point distances ``distances[i_a, j_b]`` (:func:`.collision.distance_table`) where they can be:
    ``min(d0, d1) < r`` collides and, every point moving at most ``L`` (the two sweep
    lengths), ``(d0 + d1 − L)/2 ≥ r`` is free (the bound of :func:`.collision.swept_table`); the rest
    is sampled.  ``pos``: the lattice's positions (``kin_a``'s and ``kin_b``'s shape)."""
    ia, ia1, jb, jb1 = (np.asarray(x, dtype=np.int64).reshape(-1) for x in (ia, ia1, jb, jb1))
    d0, d1 = distances[ia, jb], distances[ia1, jb1]
    length = np.asarray(kin_a.sweep_length(da) + kin_b.sweep_length(db), float)
    hit = (d0 < bsum) | (d1 < bsum)
    todo = np.nonzero(~hit & ((d0 + d1 - length) / 2 < bsum))[0]
    if len(todo):
        da_t = np.asarray(da, float)
        db_t = np.asarray(db, float)
        hit[todo] = motion_collides(kin_a, base_a, pos[ia[todo]], da_t if da_t.ndim == 1 else da_t[todo], kin_b,
                                    base_b, pos[jb[todo]], db_t if db_t.ndim == 1 else db_t[todo], bsum, tol)
    return hit


def _bisect_collides(kin_a: Kinematics, base_a: np.ndarray, qa: np.ndarray, da: np.ndarray, kin_b: Kinematics,
                     base_b: np.ndarray, qb: np.ndarray, db: np.ndarray, bsum: np.ndarray, length: np.ndarray,
                     tol: float, coarse: int) -> np.ndarray:
    """The certified sampling of the module docstring, by bisection: ``coarse`` intervals per
    entry, then every interval ``[t0, t1]`` whose bound ``(d0 + d1 − L·(t1 − t0))/2`` is below
    ``bsum`` is split, until a sample collides, every bound clears ``bsum``, or an interval's
    ``L·(t1 − t0)/2`` is at most ``tol`` (then the entry counts as colliding)."""
    hit = np.zeros(len(qa), dtype=bool)
    moving_a, moving_b = _Moving(kin_a, base_a, qa, da), _Moving(kin_b, base_b, qb, db)

    def dist(e: np.ndarray, t: np.ndarray) -> np.ndarray:
        out = np.empty(len(e))
        for lo in range(0, len(e), CHUNK):
            i, tt = e[lo:lo + CHUNK], t[lo:lo + CHUNK]
            out[lo:lo + CHUNK] = segment_distance_xy(*moving_a.coords(i, tt), *moving_b.coords(i, tt))
        return out

    grid = np.linspace(0.0, 1.0, coarse + 1)
    e = np.repeat(np.arange(len(qa)), coarse + 1)
    d = dist(e, np.tile(grid, len(qa))).reshape(len(qa), coarse + 1)
    hit |= (d < bsum[:, None]).any(axis=1)
    ee, ii = (g.ravel() for g in np.meshgrid(np.arange(len(qa)), np.arange(coarse), indexing="ij"))
    # the open intervals, one array per field: entry, t0, t1, d(t0), d(t1)
    rows = (ee, grid[ii], grid[ii + 1], d[ee, ii], d[ee, ii + 1])
    while len(rows[0]):
        left = ~hit[rows[0]]
        e, t0, t1, d0, d1 = rows = tuple(x[left] for x in rows)
        span = length[e] * (t1 - t0)
        open_ = (d0 + d1 - span) / 2 < bsum[e]
        stuck = open_ & (span / 2 <= tol)
        hit[e[stuck]] = True  # conservative at the tolerance
        e, t0, t1, d0, d1 = (x[open_ & ~stuck & ~hit[e]] for x in rows)
        if not len(e):
            break
        mid = (t0 + t1) / 2
        dm = dist(e, mid)
        hit[e[dm < bsum[e]]] = True
        rows = (np.concatenate([e, e]), np.concatenate([t0, mid]), np.concatenate([mid, t1]),
                np.concatenate([d0, dm]), np.concatenate([dm, d1]))
    return hit


def turn_collides(kin_m: Kinematics, base_m: Any, qm: Any, joint: int, delta: Any,
                  kin_s: Kinematics, base_s: Any, qs: Any, bsum: Any) -> np.ndarray:
    """Exact swept check of single-joint moves: does the mover (at ``qm``, ``(E, J)``) moving
    ``joint`` by ``delta`` (``(E,)``) come closer than ``bsum`` to the other standing at ``qs``?

    The least distance over the move is :func:`.sweep.rotation_clearance` of the mover's
    segment turned by :meth:`Kinematics.rotation`; bases are ``(E, 2)`` or ``(2,)``.
    """
    qm, qs = np.asarray(qm, float), np.asarray(qs, float)
    base_m, base_s = np.asarray(base_m, float), np.asarray(base_s, float)
    delta, bsum = np.asarray(delta, float), np.asarray(bsum, float)
    out = np.empty(len(qm), dtype=bool)
    for lo in range(0, len(qm), CHUNK):
        sl = slice(lo, lo + CHUNK)
        bm = base_m[sl] if base_m.ndim == 2 else base_m
        bs = base_s[sl] if base_s.ndim == 2 else base_s
        d = np.broadcast_to(delta, (len(qm),))[sl]
        centre, angle = kin_m.rotation(qm[sl], joint, d)
        clearance = rotation_clearance(placed_segments(kin_m, bm, qm[sl]), centre + bm, angle,
                                       placed_segments(kin_s, bs, qs[sl]))
        out[sl] = clearance < np.broadcast_to(bsum, (len(qm),))[sl]
    return out


class _Moving:
    """One side of :func:`_bisect_collides`' entries: robot ``kin`` at ``base`` ``(E, 2)``,
    moving from ``q`` by ``d`` (``(E, J)``).

    :meth:`coords` places its colliding segment at fractions ``t`` of some entries' motions as
    the four coordinate rows of :func:`.segments.segment_distance_xy`: for the chain robots
    (alpha-beta, rotary) it takes :func:`.chain.chain_segment_rows` (the formula on contiguous
    one-dimensional arrays) and adds the base: the same numbers bit for bit as
    ``segment_coords(placed_segments(kin, base[i], q[i] + t·d[i]))``, without the interleaved
    ``(n, 2, 2)`` arrays whose length-2 inner loops cost most of that; any other kinematics
    goes through :func:`placed_segments`.
    """

    def __init__(self, kin: Kinematics, base: np.ndarray, q: np.ndarray, d: np.ndarray):
        self.kin, self.base = kin, base
        self.chain = kin.chain() if isinstance(kin, (AlphaBeta, Rotary)) else None
        self.q_t, self.d_t = np.ascontiguousarray(q.T), np.ascontiguousarray(d.T)  # (J, E): one row a joint
        self.bx, self.by = np.ascontiguousarray(base[:, 0]), np.ascontiguousarray(base[:, 1])

    def coords(self, i: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, ...]:
        """``(px, py, qx, qy)`` of the segment of entries ``i`` at fractions ``t`` (``(n,)``, mm)."""
        q = np.empty((len(self.q_t), len(i)))
        for joint, (qj, dj) in enumerate(zip(self.q_t, self.d_t)):
            q[joint] = qj[i] + t * dj[i]
        if self.chain is None:
            return tuple(segment_coords(placed_segments(self.kin, self.base[i], q.T)))
        l1, segment = self.chain
        px, py, qx, qy = chain_segment_rows(l1, segment, *self.kin.chain_angles(q.T))
        bx, by = self.bx[i], self.by[i]
        return px + bx, py + by, qx + bx, qy + by

