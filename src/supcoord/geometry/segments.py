"""Distances between points and segments in the plane (numpy, broadcast over leading axes).

Point–segment: ``dist(p, [a, b]) = |p − (a + t·(b − a))|`` with
``t = clamp(((p − a)·(b − a)) / |b − a|², 0, 1)`` (``t = 0`` for a point-like segment).

Segment–segment: 0 if the segments cross (each one's end points lie strictly on both
sides of the other's line), otherwise the smallest of the four endpoint-to-segment
distances.

This is the one implementation used by the collision tables, the planners and the
paper's coupled model; the validator (:mod:`supcoord.problems.validate`) keeps an
independent algorithm on purpose.

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.2 and §5.1.9.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["segment_distance", "segment_distance_xy", "segment_coords", "point_segment_distance"]


#: elements per block of a long computation: numpy's temporaries then come from the heap instead
#: of fresh memory maps and stay in cache (60,000 segment pairs: 116 ns each at once, 42 ns in
#: blocks; ``benchmarks/bench_tables.py``)
BLOCK = 8192


def _psd(px, py, ax, ay, bx, by):
    """Point–segment distance on components (arrays broadcast)."""
    ux, uy = bx - ax, by - ay
    wx, wy = px - ax, py - ay
    den = ux * ux + uy * uy
    t = np.minimum(np.maximum((wx * ux + wy * uy) / np.where(den > 0, den, 1.0), 0.0), 1.0)  # clamp, faster than clip
    dx, dy = wx - t * ux, wy - t * uy
    return np.sqrt(dx * dx + dy * dy)


def point_segment_distance(p: Any, a: Any, b: Any) -> np.ndarray:
    """Distance from points ``p`` to segments ``[a, b]`` (``(..., 2)`` arrays, broadcast)."""
    p, a, b = np.asarray(p, float), np.asarray(a, float), np.asarray(b, float)
    return _psd(p[..., 0], p[..., 1], a[..., 0], a[..., 1], b[..., 0], b[..., 1])


def segment_distance(p0: Any, p1: Any, q0: Any, q1: Any) -> np.ndarray:
    """Distance between segments ``[p0, p1]`` and ``[q0, q1]`` (``(..., 2)`` arrays, broadcast).

    >>> float(segment_distance([0, 0], [2, 0], [1, 1], [1, 3]))
    1.0
    >>> float(segment_distance([0, 0], [2, 2], [0, 2], [2, 0]))   # crossing
    0.0
    """
    p0, p1, q0, q1 = (np.asarray(v, float) for v in (p0, p1, q0, q1))
    return segment_distance_xy(p0[..., 0], p0[..., 1], p1[..., 0], p1[..., 1],
                               q0[..., 0], q0[..., 1], q1[..., 0], q1[..., 1])


def segment_coords(segments: np.ndarray) -> np.ndarray:
    """Segments ``(..., 2, 2)`` as contiguous coordinate rows ``(4, N)``: ``px, py, qx, qy``
    (the arguments of :func:`segment_distance_xy`)."""
    return np.ascontiguousarray(np.reshape(segments, (-1, 4)).T)


def segment_distance_xy(ax: Any, ay: Any, bx: Any, by: Any, cx: Any, cy: Any, dx: Any, dy: Any) -> np.ndarray:
    """:func:`segment_distance` of ``[(ax, ay), (bx, by)]`` and ``[(cx, cy), (dx, dy)]`` given as
    coordinate arrays (broadcast): the same numbers, faster on contiguous arrays than on the
    interleaved ``(..., 2)`` ones.  Long 1-D inputs go in blocks of :data:`BLOCK`."""
    coords = (ax, ay, bx, by, cx, cy, dx, dy)
    n = len(ax) if isinstance(ax, np.ndarray) and ax.ndim == 1 else 0
    if n <= 2 * BLOCK or any(not isinstance(v, np.ndarray) or v.shape != (n,) for v in coords):
        return _segment_distance_xy(*coords)
    out = np.empty(n)
    for lo in range(0, n, BLOCK):
        out[lo:lo + BLOCK] = _segment_distance_xy(*(v[lo:lo + BLOCK] for v in coords))
    return out


def _segment_distance_xy(ax, ay, bx, by, cx, cy, dx, dy):
    """:func:`segment_distance_xy` in one pass (the module docstring's formula).

    Each difference is formed once and serves both the point–segment distances and the
    crossing test, and the square root is taken once, of the least squared distance (a
    correctly rounded square root is monotonic, so ``sqrt(min(·))`` is ``min(sqrt(·))``):
    the numbers of the four :func:`_psd` calls, bit for bit, with about a third fewer
    array operations."""
    ux, uy, vx, vy = bx - ax, by - ay, dx - cx, dy - cy
    den_u, den_v = ux * ux + uy * uy, vx * vx + vy * vy
    den_u, den_v = np.where(den_u > 0, den_u, 1.0), np.where(den_v > 0, den_v, 1.0)
    cax, cay, dax, day = cx - ax, cy - ay, dx - ax, dy - ay  # c, d from a
    acx, acy, bcx, bcy = ax - cx, ay - cy, bx - cx, by - cy  # a, b from c
    d2 = np.minimum(np.minimum(_psd2(acx, acy, vx, vy, den_v), _psd2(bcx, bcy, vx, vy, den_v)),
                    np.minimum(_psd2(cax, cay, ux, uy, den_u), _psd2(dax, day, ux, uy, den_u)))
    o1 = ux * cay - uy * cax  # side of q0 w.r.t. line p
    o2 = ux * day - uy * dax  # side of q1
    o3 = vx * acy - vy * acx  # side of p0 w.r.t. line q
    o4 = vx * bcy - vy * bcx  # side of p1
    crossing = (o1 * o2 < 0) & (o3 * o4 < 0)
    return np.where(crossing, 0.0, np.sqrt(d2))


def _psd2(wx, wy, ux, uy, den):
    """Squared :func:`_psd` of the point at ``w`` from a segment's start, the segment along
    ``u``, ``den`` = ``|u|²`` (1 where that is 0)."""
    t = np.minimum(np.maximum((wx * ux + wy * uy) / den, 0.0), 1.0)
    ex, ey = wx - t * ux, wy - t * uy
    return ex * ex + ey * ey
