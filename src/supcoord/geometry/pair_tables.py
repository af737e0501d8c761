"""The collision tables of one pair of robots: static, distance, swept and simultaneous.

The definitions are those of :mod:`.collision` (which re-exports these functions and keeps
the tables of a whole layout, :class:`.collision.CollisionTables`): a pair collides when its
colliding segments come closer than the buffer sum; a swept entry is a one-joint move of
the mover against the other standing, decided exactly (:func:`.sweep.rotation_clearance`);
a simultaneous entry is both moving at once, by certified sampling (:mod:`.motion`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError
from .batch import fill_reversed, reversals
from .joint_space import MAX_POSITIONS, Kinematics
from .motion import CHUNK, DEFAULT_TOL, placed_segments, prefiltered_motion_collides, turn_collides
from .segments import segment_distance

__all__ = ["MAX_TABLE_ENTRIES", "static_table", "distance_table", "swept_table", "simultaneous_table"]

#: largest table (position pairs of one neighbour pair) built explicitly; finer
#: discretisations must be encoded otherwise (e.g. per-joint symbolic constraints)
MAX_TABLE_ENTRIES = MAX_POSITIONS**2

def static_table(kin: Kinematics, base_a: Any, base_b: Any, bsum: float,
                 kin_b: Kinematics | None = None) -> np.ndarray:
    """``T[i, j]``: positioner ``a`` at position ``i`` collides with ``b`` at ``j`` (flat indices)."""
    return distance_table(kin, base_a, base_b, kin_b) < bsum


def distance_table(kin: Kinematics, base_a: Any, base_b: Any, kin_b: Kinematics | None = None) -> np.ndarray:
    """``D[i, j]`` = distance between the colliding segments of ``a`` at ``i`` and ``b`` at ``j``."""
    kin_b = kin_b or kin
    if kin.n_positions * kin_b.n_positions > MAX_TABLE_ENTRIES:
        raise InputError(f"a collision table of {kin.n_positions} x {kin_b.n_positions} positions exceeds "
                         f"{MAX_TABLE_ENTRIES} entries; use fewer steps per joint", value=kin.n_positions)
    sa = placed_segments(kin, base_a, kin.all_positions())
    sb = placed_segments(kin_b, base_b, kin_b.all_positions())
    out = np.empty((len(sa), len(sb)))
    rows = max(1, CHUNK * 4 // max(len(sb), 1))
    for lo in range(0, len(sa), rows):
        s = sa[lo:lo + rows, None]
        out[lo:lo + rows] = segment_distance(s[..., 0, :], s[..., 1, :], sb[None, :, 0], sb[None, :, 1])
    return out


def swept_table(kin: Kinematics, base_a: Any, base_b: Any, bsum: float, mover: int = 0, *,
                kin_b: Kinematics | None = None, distances: np.ndarray | None = None) -> np.ndarray:
    """``W[m, i, j]``: the one-step move ``moves()[m]`` of the mover collides somewhere.

    ``mover = 0``: ``a`` moves from position ``i`` while ``b`` stands at ``j``; ``mover = 1``:
    ``b`` moves from ``j`` while ``a`` stands at ``i`` (indices are always ``[i_a, j_b]``).
    A move past a hard stop is reported as blocked (``True``).  Every entry where the
    start or end pose collides statically is ``True``.

    The end-point distances ``d0``, ``d1`` (from :func:`distance_table`) settle most
    entries: ``min(d0, d1) < r`` collides, and since the distance changes at rate at most
    ``L`` (the sweep length), ``d(t) ≥ max(d0 − tL, d1 − (1−t)L) ≥ (d0 + d1 − L)/2``, so
    ``(d0 + d1 − L)/2 ≥ r`` is free; the rest is decided exactly by :func:`turn_collides`.
    A reversed move travels the poses of its forward move (:meth:`.Kinematics.reversed_moves`),
    so its rows are copied from the forward move's (:func:`.batch.fill_reversed`).
    """
    kin_b = kin_b or kin
    if distances is None:
        distances = distance_table(kin, base_a, base_b, kin_b)
    D = distances if mover == 0 else distances.T          # rows: the mover's positions
    mk, sk = (kin, kin_b) if mover == 0 else (kin_b, kin)
    pm, ps = mk.all_positions(), sk.all_positions()
    out = np.ones((len(mk.moves()), len(pm), len(ps)), dtype=bool)
    steps = reversals(mk)
    reversed_ = {r for r, *_ in steps}
    for m, (joint, delta) in enumerate(mk.moves()):
        if m in reversed_:
            continue
        nxt, ok = mk.step_array(pm, joint, delta)
        valid = np.nonzero(ok)[0]
        d = np.zeros(mk.n_joints)
        d[joint] = delta
        d0, d1 = D[valid], D[mk.flat_index(nxt[valid])]
        length = float(mk.sweep_length(d))
        hit = (d0 < bsum) | (d1 < bsum)
        free = ~hit & ((d0 + d1 - length) / 2 >= bsum)
        block = ~hit & ~free
        ii, jj = np.nonzero(block)
        res = hit.copy()
        if len(ii):
            bm, bs = (base_a, base_b) if mover == 0 else (base_b, base_a)
            res[ii, jj] = turn_collides(mk, bm, pm[valid][ii], joint, delta, sk, bs, ps[jj], bsum)
        out[m, valid] = res
    fill_reversed(out, steps)
    return out if mover == 0 else np.swapaxes(out, 1, 2)


def simultaneous_table(kin: Kinematics, base_a: Any, base_b: Any, bsum: float, tol: float = DEFAULT_TOL,
                       distances: np.ndarray | None = None, kin_b: Kinematics | None = None) -> np.ndarray:
    """``S[u, v, i, j]``: ``a`` doing move ``u`` from ``i`` while ``b`` does move ``v`` from ``j`` collides.

    Moves are indexed ``0`` = stand still, ``1 + m`` = ``kin.moves()[m]``; so ``S[0, 0]`` is
    the static table and ``S[1 + m, 0]``/``S[0, 1 + m]`` the swept tables of either mover.
    Both positioners move linearly in joint space over the same time ``t ∈ [0, 1]`` (the
    validator's interpolation); a move past a hard stop is blocked (``True``).  Same
    end-point prefilter and certified sampling as :func:`swept_table`.  ``kin_b``: ``b``'s
    kinematics when it differs from ``a``'s (same joints and steps, its own lattice or arms).
    """
    kin_b = kin_b or kin
    if distances is None:
        distances = distance_table(kin, base_a, base_b, kin_b)
    pos = kin.all_positions()
    moves = [None] + kin.moves()
    out = np.ones((len(moves), len(moves), len(pos), len(pos)), dtype=bool)
    nxt_idx, valid, deltas = [], [], []
    for mv in moves:
        d = np.zeros(kin.n_joints)
        if mv is None:
            nxt_idx.append(np.arange(len(pos)))
            valid.append(np.ones(len(pos), dtype=bool))
        else:
            joint, delta = mv
            d[joint] = delta
            nxt, ok = kin.step_array(pos, joint, delta)
            nxt_idx.append(np.where(ok, kin.flat_index(np.where(ok[:, None], nxt, pos)), 0))
            valid.append(ok)
        deltas.append(d)
    for u in range(len(moves)):
        for v in range(len(moves)):
            vi, vj = np.nonzero(valid[u])[0], np.nonzero(valid[v])[0]
            ii, jj = (x.ravel() for x in np.meshgrid(vi, vj, indexing="ij"))
            res = prefiltered_motion_collides(kin, base_a, pos, ii, nxt_idx[u][ii], deltas[u], kin_b, base_b, jj,
                                              nxt_idx[v][jj], deltas[v], bsum, distances, tol)
            out[u, v][np.ix_(vi, vj)] = res.reshape(len(vi), len(vj))
    return out
