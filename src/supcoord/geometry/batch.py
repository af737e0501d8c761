"""Swept tables of many pairs at once, for layouts whose robots each have their own geometry.

:func:`.collision.swept_table` decides one pair's moves with a few numpy calls each; a real
focal plane (each robot its own arms and lattice) has thousands of distinct pairs, and
the time then goes into the calls, not the arithmetic.  :func:`batch_swept` computes the
same tables — the same end-point prefilter and the same exact closed form
(:func:`.sweep.rotation_clearance`) on the same numbers — for a whole chunk of pairs, with
one clearance call over every undecided entry of the chunk.  Each robot's segments,
successors and rotations are computed once per distinct kinematics.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .joint_space import Kinematics
from .segments import segment_distance
from .sweep import rotation_clearance

__all__ = ["batch_swept", "KinematicsArrays"]


class KinematicsArrays:
    """One kinematics' positions as arrays: segments ``S[i]`` (relative to the base) and, per
    move ``m``, the successor ``nxt[m, i]`` (−1 past a hard stop), the turn's centre and
    angle (:meth:`Kinematics.rotation`) and the sweep length."""

    def __init__(self, kin: Kinematics):
        pos = kin.all_positions()
        self.segments = kin.segments(pos)
        moves = kin.moves()
        self.nxt = np.full((len(moves), len(pos)), -1, dtype=np.int64)
        self.centre = np.zeros((len(moves), len(pos), 2))
        self.angle = np.zeros((len(moves), len(pos)))
        self.length = np.zeros(len(moves))
        for m, (joint, delta) in enumerate(moves):
            nxt, ok = kin.step_array(pos, joint, delta)
            idx = np.nonzero(ok)[0]
            self.nxt[m, idx] = kin.flat_index(nxt[idx])
            if len(idx):
                c, a = kin.rotation(pos[idx], joint, np.full(len(idx), float(delta)))
                self.centre[m, idx], self.angle[m, idx] = c, a
            d = np.zeros(kin.n_joints)
            d[joint] = delta
            self.length[m] = float(kin.sweep_length(d))


def batch_swept(arrays_a: list[KinematicsArrays], arrays_b: list[KinematicsArrays], offsets: Any,
                bsums: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``[(D, W0, W1), …]`` for pairs ``k`` with ``a`` at the origin and ``b`` at ``offsets[k]``:
    the distance table ``D[i, j]`` and the swept tables of ``a`` moving (``W0[m, i, j]``) and of
    ``b`` moving (``W1[m, i, j]``), as :func:`.collision.swept_table` defines them."""
    offsets = np.asarray(offsets, float).reshape(-1, 2)
    out: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    jobs: list[tuple] = []  # undecided entries: (table, m, i, j, seg, centre, angle, other, bsum)
    for ka, kb, off, bsum in zip(arrays_a, arrays_b, offsets, np.asarray(bsums, float)):
        sa, sb = ka.segments, kb.segments + off
        dist = segment_distance(sa[:, None, 0], sa[:, None, 1], sb[None, :, 0], sb[None, :, 1])
        tables = []
        for mover, (km, seg_m, seg_s, shift, d) in enumerate(((ka, sa, sb, 0.0, dist),
                                                                (kb, sb, sa, off, dist.T))):
            w = np.ones((len(km.nxt),) + d.shape, dtype=bool)
            for m in range(len(km.nxt)):
                valid = np.nonzero(km.nxt[m] >= 0)[0]
                d0, d1 = d[valid], d[km.nxt[m, valid]]
                hit = (d0 < bsum) | (d1 < bsum)
                free = ~hit & ((d0 + d1 - km.length[m]) / 2 >= bsum)
                w[m, valid] = hit
                ii, jj = np.nonzero(~hit & ~free)
                if len(ii):
                    rows = valid[ii]
                    jobs.append((w, m, rows, jj, seg_m[rows], km.centre[m, rows] + shift, km.angle[m, rows],
                                 seg_s[jj], bsum))
            tables.append(w)
        out.append((dist, tables[0], np.swapaxes(tables[1], 1, 2)))
    if jobs:
        clearance = rotation_clearance(np.concatenate([j[4] for j in jobs]), np.concatenate([j[5] for j in jobs]),
                                       np.concatenate([j[6] for j in jobs]), np.concatenate([j[7] for j in jobs]))
        at = 0
        for w, m, rows, cols, _, _, _, _, bsum in jobs:
            w[m, rows, cols] = clearance[at:at + len(rows)] < bsum
            at += len(rows)
    return out
