"""Two motions at independent times: do their swept sets stay apart?

A robot's motion ``q → q + d`` (every joint turning linearly in angle, a lattice step at most)
sweeps its colliding segment through the poses ``S_a(s)``, ``s ∈ [0, 1]``.  Two robots
making one motion each, *at whatever times*, meet at some pair of poses ``(S_a(s), S_b(t))``
with ``s`` and ``t`` unrelated.  The motions are **apart** when

    ``min_{s, t ∈ [0, 1]} dist(S_a(s), S_b(t)) ≥ bsum``

(``bsum`` the pair's buffer sum): then no timing of the two motions, and no pose either
robot holds before or after its motion, brings them together.  This is what lets a timing
(:mod:`supcoord.problems.timing`) run two neighbours' moves out of the plan's step order.

**Certificate.**  Every point of ``S_a`` travels at most ``L_a`` (:meth:`Kinematics.sweep_length`)
over the motion, so ``dist(S_a(s), S_b(t))`` is ``L_a``-Lipschitz in ``s`` and ``L_b``-Lipschitz
in ``t``: over a cell ``[s0, s1] × [t0, t1]`` it is at least its value at the centre minus
``(L_a·(s1 − s0) + L_b·(t1 − t0))/2``.  :func:`sweeps_apart` starts every pair from the
whole square (its centre: the two middle poses) and splits, breadth-first and for all
pairs at once on arrays, each open cell across the side along which its bound is larger,
until a centre is closer than ``bsum`` (not apart: a proven meeting), every cell clears
``bsum`` (apart), or a cell's bound is within ``tol`` of deciding or a pair has needed
more than ``max_cells`` cells (counted as *not apart*: the answer errs only towards keeping
the plan's order).

References
----------
- P. Hansen, B. Jaumard, Lipschitz optimization, in *Handbook of Global Optimization*,
  Kluwer 1995 (branch and bound on Lipschitz bounds in several variables).
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.9 (segment distance).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .chain import chain_segments
from .segments import segment_distance_xy

__all__ = ["MOTION_FIELDS", "sweeps_apart"]

#: the columns of a motion row: base, first link, segment in the second link's frame, chain
#: angles at the start and their turns (radians), as :func:`.chain_motion._pose` reads them
MOTION_FIELDS = ("base_x", "base_y", "l1", "s0x", "s0y", "s1x", "s1y", "a0", "da", "b0", "db")
#: a cell whose bound is this close (mm) to deciding counts as not apart
DEFAULT_TOL = 1e-3
#: cells examined for one pair before it counts as not apart
MAX_CELLS = 4096


def sweeps_apart(motions_a: np.ndarray, length_a: np.ndarray, motions_b: np.ndarray, length_b: np.ndarray,
                 bsum: np.ndarray, tol: float = DEFAULT_TOL, max_cells: int = MAX_CELLS) -> np.ndarray:
    """``(M,)`` Booleans: are motions ``motions_a[i]`` and ``motions_b[i]`` (``(M, 11)`` rows of
    :data:`MOTION_FIELDS`, travel bounds ``length_a[i]``, ``length_b[i]`` mm) apart by
    ``bsum[i]``, at independent times?  The module's certificate, every pair's cells split
    breadth-first on arrays; False when undecided."""
    if not tol > 0:
        raise InputError(f"tol must be positive, got {tol!r}", value=tol)
    a, b = np.asarray(motions_a, float).reshape(-1, 11), np.asarray(motions_b, float).reshape(-1, 11)
    la, lb = np.asarray(length_a, float).reshape(-1), np.asarray(length_b, float).reshape(-1)
    if not (len(a) == len(b) == len(la) == len(lb)):
        raise InputError(f"sweeps_apart needs rows of equal count, got {len(a)}, {len(b)}, {len(la)}, {len(lb)}",
                         value=None)
    bsum = np.broadcast_to(np.asarray(bsum, float), la.shape)
    apart = np.ones(len(a), dtype=bool)
    cells_seen = np.zeros(len(a), dtype=np.int64)
    # open cells: pair, lower corner (s0, t0) and widths (ws, wt)
    pair = np.arange(len(a))
    s0, t0, ws, wt = np.zeros(len(a)), np.zeros(len(a)), np.ones(len(a)), np.ones(len(a))
    while len(pair):
        cells_seen += np.bincount(pair, minlength=len(a))
        d = segment_distance_xy(*_placed(a[pair], s0 + ws / 2), *_placed(b[pair], t0 + wt / 2))
        slack = (la[pair] * ws + lb[pair] * wt) / 2
        need = bsum[pair]
        cleared = d - slack >= need
        # a centre closer than bsum meets; a cell within tol of deciding stays undecided
        fail = (d < need) | (~cleared & (slack <= tol))
        apart[pair[fail]] = False
        apart[cells_seen > max_cells] = False
        keep = ~cleared & apart[pair]
        pair, s0, t0, ws, wt = pair[keep], s0[keep], t0[keep], ws[keep], wt[keep]
        along_s = la[pair] * ws >= lb[pair] * wt  # split the side along which the bound is larger
        ws, wt = np.where(along_s, ws / 2, ws), np.where(along_s, wt, wt / 2)
        pair = np.concatenate([pair, pair])
        s0 = np.concatenate([s0, np.where(along_s, s0 + ws, s0)])
        t0 = np.concatenate([t0, np.where(along_s, t0, t0 + wt)])
        ws, wt = np.concatenate([ws, ws]), np.concatenate([wt, wt])
    return apart


def _placed(m: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, ...]:
    """The placed segments of motion rows ``m`` at times ``s``, as coordinate arrays ``px, py, qx, qy``."""
    seg = chain_segments(m[:, 2], m[:, 3:7].reshape(-1, 2, 2), m[:, 7] + s * m[:, 8], m[:, 9] + s * m[:, 10])
    seg = seg + m[:, None, 0:2]
    return seg[:, 0, 0], seg[:, 0, 1], seg[:, 1, 0], seg[:, 1, 1]
