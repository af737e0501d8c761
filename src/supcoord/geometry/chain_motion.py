"""One simultaneous motion of two robots, checked on Python floats: the planners' single queries.

The greedy descent and the schedules ask, one motion at a time and tens of thousands of
times on a real focal plane, whether two neighbours moving together (or one robot moving
two joints at once) stay clear.  :func:`.motion.motion_collides` answers on numpy arrays;
on a single motion its time goes into numpy's per-call overhead (tens of microseconds for
each of its dozens of calls), not into arithmetic.  :func:`chain_motion_collides` answers
the same question with the same certificate on floats, about ten times faster per query
(``benchmarks/results/instrument.md``); both are kept because the tables need the arrays.

**Poses.**  A robot's colliding segment is a planar two-link chain (:meth:`Kinematics.chain`):
the elbow ``e = base + l1·(cos a, sin a)`` and the end points ``e + R(a + b)·s_k``.  Between
two neighbouring positions every joint turns linearly in angle (:meth:`Kinematics.chain_angles`
interpolates linearly), so in a move of at most one position per joint the pose at time
``t ∈ [0, 1]`` is the chain at ``(a0 + t·Δa, b0 + t·Δb)``, ``(a0, b0)`` and ``(a0 + Δa, b0 + Δb)``
the chain angles of the two positions (a wrapping joint continues one position past its
ends, as the fractional positions of :meth:`Kinematics.segments` do).

**Certificate** (that of :mod:`.motion`, with the same numbers): every point of both
segments moves at most ``L = sweep_length(d_a) + sweep_length(d_b)``
(:meth:`Kinematics.sweep_length`), so the distance ``d(t)`` is ``L``-Lipschitz and over
``[t0, t1]`` at least ``(d(t0) + d(t1) − L·(t1 − t0))/2``.  Starting from ``coarse``
equal intervals, an interval whose bound is below ``bsum`` is split at its middle until a
sample collides (a proven collision), every bound clears ``bsum`` (proven free), or
``L·(t1 − t0)/2 ≤ tol`` (counted as colliding: conservative by at most ``tol`` mm).  The
verdict is that of the whole refinement tree, so it does not depend on the order in
which intervals are split: this depth-first search gives the vectorised breadth-first
one's verdicts, up to floating-point rounding of the distances (``tests/geometry/test_chain_motion.py``).

References
----------
- P. Hansen, B. Jaumard, S.-H. Lu, Global optimization of univariate Lipschitz functions,
  Mathematical Programming 55, 1992 (bounds from Lipschitz constants, interval splitting).
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.2 and §5.1.9
  (:func:`.segments.segment_distance`, whose formula :func:`segment_distance_floats` repeats).
"""

from __future__ import annotations

import weakref
from math import cos, sin, sqrt
from typing import Callable, Sequence

import numpy as np

from ..errors import InputError
from .joint_space import Kinematics

__all__ = ["ChainGeometry", "chain_geometry", "chain_motion_collides", "segment_distance_floats"]

#: default tolerance (mm), as :data:`.motion.DEFAULT_TOL`
DEFAULT_TOL = 1e-6


class ChainGeometry:
    """One kinematics as floats: its chain (:meth:`Kinematics.chain`), the chain angles of the
    positions asked for (memoised) and the sweep length of each delta (memoised).  It refers
    to its kinematics weakly (:func:`chain_geometry` keeps one per live kinematics object):
    whoever makes one keeps the kinematics alive while using it."""

    __slots__ = ("_kin", "l1", "s0x", "s0y", "s1x", "s1y", "_angles", "_lengths", "_ends")

    def __init__(self, kin: Kinematics):
        self._kin = weakref.ref(kin)
        self.l1, ((self.s0x, self.s0y), (self.s1x, self.s1y)) = kin.chain()
        self._angles: dict[tuple[int, ...], tuple[float, float]] = {}
        self._lengths: dict[tuple[int, ...], float] = {}
        self._ends: dict[tuple[tuple[int, ...], tuple[int, ...]], tuple[float, ...]] = {}

    @property
    def kin(self) -> Kinematics:
        """The kinematics described."""
        kin = self._kin()
        if kin is None:
            raise RuntimeError("internal error: the kinematics of a ChainGeometry was collected while in use")
        return kin

    def angles(self, q: tuple[int, ...]) -> tuple[float, float]:
        """Chain angles ``(a, b)`` of the (integer, possibly one past a wrapping end) position ``q``."""
        out = self._angles.get(q)
        if out is None:
            a, b = self.kin.chain_angles(np.asarray(q, dtype=float))
            out = self._angles[q] = (float(a), float(b))
        return out

    def length(self, d: tuple[int, ...]) -> float:
        """:meth:`Kinematics.sweep_length` of the delta ``d``."""
        out = self._lengths.get(d)
        if out is None:
            out = self._lengths[d] = float(self.kin.sweep_length(np.asarray(d, dtype=float)))
        return out

    def ends(self, q: tuple[int, ...], d: tuple[int, ...]) -> tuple[float, ...]:
        """The motion ``q → q + d`` as :func:`chain_motion_collides` evaluates it, memoised:
        ``(a0, Δa, b0, Δb, x0, y0, x1, y1, x0', y0', x1', y1')``, the chain angles at the start
        and their changes, then the segment's end points at ``t = 0`` and ``t = 1`` relative to
        the base (:func:`_pose` of a robot at the origin: placing it adds the base last, so
        these are the same numbers)."""
        key = (q, d)
        out = self._ends.get(key)
        if out is None:
            a0, b0 = self.angles(q)
            a1, b1 = self.angles(tuple(x + v for x, v in zip(q, d)))
            p = (0.0, 0.0, self.l1, self.s0x, self.s0y, self.s1x, self.s1y, a0, a1 - a0, b0, b1 - b0)
            out = self._ends[key] = p[7:] + _local_pose(p, 0.0) + _local_pose(p, 1.0)
        return out


#: :func:`chain_geometry`'s results by ``id`` of their kinematics object, each dropped when
#: the object is collected (:func:`weakref.finalize`; kinematics compare by value and are
#: not hashable, and nothing is written onto them)
_CHAINS: dict[int, ChainGeometry] = {}


def chain_geometry(kin: Kinematics) -> ChainGeometry:
    """The :class:`ChainGeometry` of ``kin``, made once per kinematics object (held here, not on ``kin``)."""
    geo = _CHAINS.get(id(kin))
    if geo is None:
        geo = _CHAINS[id(kin)] = ChainGeometry(kin)
        weakref.finalize(kin, _CHAINS.pop, id(kin), None)
    return geo


def segment_distance_floats(ax: float, ay: float, bx: float, by: float,
                            cx: float, cy: float, dx: float, dy: float) -> float:
    """Distance between segments ``[(ax, ay), (bx, by)]`` and ``[(cx, cy), (dx, dy)]``: the
    formula of :func:`.segments.segment_distance` (0 if they cross, else the least of the
    four end-point-to-segment distances) on floats.

    The four point–segment distances are written out (no calls: this is the innermost
    function of every simultaneous-motion check) and compared squared, with one square root
    of the least (a correctly rounded square root is monotonic: the same number as the least
    of four roots).

    Parameters
    ----------
    ax, ay, bx, by : float
        End points of the first segment (mm).
    cx, cy, dx, dy : float
        End points of the second segment (mm).

    Returns
    -------
    float
        The least distance between the two segments (mm), 0 where they cross.

    Examples
    --------
    >>> segment_distance_floats(0.0, 0.0, 2.0, 0.0, 1.0, 1.0, 1.0, 3.0)
    1.0
    >>> segment_distance_floats(0.0, 0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 0.0)   # crossing
    0.0
    """
    ux, uy, vx, vy = bx - ax, by - ay, dx - cx, dy - cy
    cax, cay, dax, day = cx - ax, cy - ay, dx - ax, dy - ay  # c, d from a
    acx, acy, bcx, bcy = ax - cx, ay - cy, bx - cx, by - cy  # a, b from c
    if (ux * cay - uy * cax) * (ux * day - uy * dax) < 0 and (vx * acy - vy * acx) * (vx * bcy - vy * bcx) < 0:
        return 0.0
    den = vx * vx + vy * vy  # a and b from the segment [c, d]
    t = (acx * vx + acy * vy) / den if den > 0 else 0.0
    t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
    ex, ey = acx - t * vx, acy - t * vy
    least = ex * ex + ey * ey
    t = (bcx * vx + bcy * vy) / den if den > 0 else 0.0
    t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
    ex, ey = bcx - t * vx, bcy - t * vy
    least = min(least, ex * ex + ey * ey)
    den = ux * ux + uy * uy  # c and d from the segment [a, b]
    t = (cax * ux + cay * uy) / den if den > 0 else 0.0
    t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
    ex, ey = cax - t * ux, cay - t * uy
    least = min(least, ex * ex + ey * ey)
    t = (dax * ux + day * uy) / den if den > 0 else 0.0
    t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
    ex, ey = dax - t * ux, day - t * uy
    return sqrt(min(least, ex * ex + ey * ey))


def chain_motion_collides(geo_a: ChainGeometry, base_a: Sequence[float], qa: Sequence[int], da: Sequence[int],
                          geo_b: ChainGeometry, base_b: Sequence[float], qb: Sequence[int], db: Sequence[int],
                          bsum: float, tol: float = DEFAULT_TOL, coarse: int = 4) -> bool:
    """Does the simultaneous motion ``q_a → q_a + d_a``, ``q_b → q_b + d_b`` (integer positions,
    deltas of at most one position per joint, ``t ∈ [0, 1]``) bring the two colliding segments
    closer than ``bsum``?  The certificate of the module docstring."""
    if not tol > 0:
        raise InputError(f"tol must be positive, got {tol!r}", value=tol)
    qa, da, qb, db = tuple(map(int, qa)), tuple(map(int, da)), tuple(map(int, qb)), tuple(map(int, db))
    if max(map(abs, da + db), default=0) > 1:
        raise InputError(f"a single motion turns each joint by at most one position, got {da} and {db}",
                         value=[da, db])
    ea, eb = geo_a.ends(qa, da), geo_b.ends(qb, db)
    ax, ay, bx, by = float(base_a[0]), float(base_a[1]), float(base_b[0]), float(base_b[1])
    length = geo_a.length(da) + geo_b.length(db)

    # the end points first: they decide most motions (a collision at an end, or the bound of
    # the whole motion clears: then every interval's does, the distance being L-Lipschitz)
    d_start = segment_distance_floats(ea[4] + ax, ea[5] + ay, ea[6] + ax, ea[7] + ay,
                                      eb[4] + bx, eb[5] + by, eb[6] + bx, eb[7] + by)
    d_end = segment_distance_floats(ea[8] + ax, ea[9] + ay, ea[10] + ax, ea[11] + ay,
                                    eb[8] + bx, eb[9] + by, eb[10] + bx, eb[11] + by)
    if d_start < bsum or d_end < bsum:
        return True
    if (d_start + d_end - length) / 2 >= bsum:
        return False
    dist = _distance((ax, ay, geo_a.l1, geo_a.s0x, geo_a.s0y, geo_a.s1x, geo_a.s1y) + ea[:4],
                     (bx, by, geo_b.l1, geo_b.s0x, geo_b.s0y, geo_b.s1x, geo_b.s1y) + eb[:4])
    grid = [k / coarse for k in range(coarse + 1)]
    ds = [d_start] + [dist(t) for t in grid[1:-1]] + [d_end]
    if min(ds) < bsum:
        return True
    stack = [(grid[k], grid[k + 1], ds[k], ds[k + 1]) for k in range(coarse)]
    while stack:
        t0, t1, d0, d1 = stack.pop()
        span = length * (t1 - t0)
        if (d0 + d1 - span) / 2 >= bsum:
            continue  # proven free on [t0, t1]
        if span / 2 <= tol:
            return True  # undecided at the tolerance: counted as colliding
        mid = (t0 + t1) / 2
        dm = dist(mid)
        if dm < bsum:
            return True
        stack.append((t0, mid, d0, dm))
        stack.append((mid, t1, dm, d1))
    return False


def _distance(pa: tuple, pb: tuple) -> Callable[[float], float]:
    """The distance at time ``t`` of the segments of chain parameters ``pa`` and ``pb``
    (:func:`_pose` of each, then :func:`segment_distance_floats`; the same operations in the
    same order, without the calls in between: the refinement's innermost function)."""
    bx, by, l1, s0x, s0y, s1x, s1y, a0, da, b0, db = pa
    cx, cy, m1, r0x, r0y, r1x, r1y, c0, dc, e0, de = pb

    def dist(t: float) -> float:
        a = a0 + t * da
        ab = a + b0 + t * db
        ex, ey = l1 * cos(a), l1 * sin(a)
        c, s = cos(ab), sin(ab)
        f = c0 + t * dc
        ce = f + e0 + t * de
        fx, fy = m1 * cos(f), m1 * sin(f)
        k, n = cos(ce), sin(ce)
        return segment_distance_floats(ex + (s0x * c - s0y * s) + bx, ey + (s0x * s + s0y * c) + by,
                                       ex + (s1x * c - s1y * s) + bx, ey + (s1x * s + s1y * c) + by,
                                       fx + (r0x * k - r0y * n) + cx, fy + (r0x * n + r0y * k) + cy,
                                       fx + (r1x * k - r1y * n) + cx, fy + (r1x * n + r1y * k) + cy)
    return dist


def _local_pose(p: tuple, t: float) -> tuple[float, float, float, float]:
    """:func:`_pose` without adding the base ``p[:2]``: the segment relative to the base."""
    _, _, l1, s0x, s0y, s1x, s1y, a0, da, b0, db = p
    a = a0 + t * da
    ab = a + b0 + t * db
    ex, ey = l1 * cos(a), l1 * sin(a)
    c, s = cos(ab), sin(ab)
    return ex + (s0x * c - s0y * s), ey + (s0x * s + s0y * c), ex + (s1x * c - s1y * s), ey + (s1x * s + s1y * c)


def _pose(p: tuple, t: float) -> tuple[float, float, float, float]:
    """The placed segment ``(x0, y0, x1, y1)`` of chain parameters ``p`` at time ``t``."""
    bx, by, l1, s0x, s0y, s1x, s1y, a0, da, b0, db = p
    a = a0 + t * da
    ab = a + b0 + t * db
    ex, ey = l1 * cos(a), l1 * sin(a)
    c, s = cos(ab), sin(ab)
    return (ex + (s0x * c - s0y * s) + bx, ey + (s0x * s + s0y * c) + by,
            ex + (s1x * c - s1y * s) + bx, ey + (s1x * s + s1y * c) + by)
