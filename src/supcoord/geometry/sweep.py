"""Exact clearance of a rotating segment: the swept check of a single-joint move, in closed form.

Every single-joint move of the supported kinematics turns the colliding segment rigidly
about a fixed centre: the base for a rotary arm and for the alpha joint, the elbow for
the beta joint.  For a segment ``S = [P, Q]`` turned by ``φ ∈ [0, Δ]`` about ``c``
(``S(φ) = c + R(φ)(S − c)``) and a standing segment ``T = [A, B]``::

    min_φ dist(S(φ), T) = min( dist(S(0), T),
                               dist(arc(P), T), dist(arc(Q), T),           (1)
                               dist(arc⁻(A), S(0)), dist(arc⁻(B), S(0)) )

where ``arc(X)`` is the circular arc ``X`` travels (about ``c``, through ``Δ``) and
``arc⁻(X)`` the arc of a point of ``T`` turned the other way (distances are invariant
under the rotation, so ``dist(A, S(φ)) = dist(R(−φ)A, S(0))``).  Proof: the distance of
two segments is 0 when they meet and otherwise the least of the four end-point-to-segment
distances; and if ``S(φ)`` meets ``T`` at some ``φ`` but not at ``φ = 0``, then at the
first such ``φ`` an end point of one lies on the other (a transversal crossing persists
a little earlier), so one of the end-point terms of (1) is 0.

The distance from an arc to a segment is attained at a critical pair, so it is the least
of: the arc's end points to the segment; the segment's end points to the arc (radial,
where their direction lies inside the arc); the two circle points ``c ± ρ·n`` (``n`` the
segment's unit normal) where they lie inside the arc; and 0 where the segment's line cuts
the circle inside the arc and inside the segment.  Every candidate is the distance of an
actual pair of points, so the least one is the exact minimum (up to floating-point
rounding, far below a micrometre).

This is what makes the swept collision tables exact: ``W[m, i, j] = min < r_a + r_b``,
with no tolerance (:func:`supcoord.geometry.collision.swept_table`).

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.2 (point and
  segment), §5.3.2 (segment against circle, the intersection quadratic).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .segments import point_segment_distance, segment_distance

__all__ = ["arc_segment_distance", "rotation_clearance"]

_TWO_PI = 2.0 * np.pi


def _rotate(x: np.ndarray, c: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """``c + R(angle)(x − c)`` (``(..., 2)`` points, ``angle`` ``(...)``)."""
    ca, sa = np.cos(angle), np.sin(angle)
    dx, dy = x[..., 0] - c[..., 0], x[..., 1] - c[..., 1]
    return np.stack([c[..., 0] + ca * dx - sa * dy, c[..., 1] + sa * dx + ca * dy], axis=-1)


def _in_arc(direction: np.ndarray, start: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Does the polar angle ``direction`` lie on the arc from ``start`` turning by ``angle`` (signed)?"""
    gone = np.mod((direction - start) * np.where(angle < 0, -1.0, 1.0), _TWO_PI)
    return gone <= np.abs(angle)


def arc_segment_distance(center: Any, point: Any, angle: Any, a: Any, b: Any) -> np.ndarray:
    """Least distance between the arc ``point`` travels about ``center`` through ``angle``
    (radians, signed, ``|angle| < 2π``) and the segment ``[a, b]`` (arrays broadcast).

    >>> float(arc_segment_distance([0, 0], [1, 0], np.pi / 2, [2, 2], [2, -2]))   # arc never nearer than x = 1
    1.0
    >>> float(arc_segment_distance([0, 0], [1, 0], np.pi, [-2, 0.5], [2, 0.5]))   # the arc cuts the segment
    0.0
    """
    c, p, a, b = (np.asarray(v, float) for v in (center, point, a, b))
    angle = np.asarray(angle, float)
    shape = np.broadcast_shapes(c.shape, p.shape, a.shape, b.shape, angle.shape + (2,))
    c, p, a, b = (np.broadcast_to(v, shape) for v in (c, p, a, b))
    angle = np.broadcast_to(angle, shape[:-1])
    rel = p - c
    rho = np.hypot(rel[..., 0], rel[..., 1])
    start = np.arctan2(rel[..., 1], rel[..., 0])
    end = _rotate(p, c, angle)
    best = np.minimum(point_segment_distance(p, a, b), point_segment_distance(end, a, b))
    # the segment's end points against the arc, radially where they face it
    for x in (a, b):
        rx = x - c
        dx = np.hypot(rx[..., 0], rx[..., 1])
        inside = _in_arc(np.arctan2(rx[..., 1], rx[..., 0]), start, angle)
        best = np.where(inside, np.minimum(best, np.abs(dx - rho)), best)
    # interior pairs: the circle points where the radius is normal to the segment
    u = b - a
    length = np.hypot(u[..., 0], u[..., 1])
    nonzero = length > 0
    safe = np.where(nonzero, length, 1.0)
    n = np.stack([-u[..., 1] / safe, u[..., 0] / safe], axis=-1)
    for sign in (1.0, -1.0):
        x = c + sign * rho[..., None] * n
        inside = nonzero & _in_arc(np.arctan2(sign * n[..., 1], sign * n[..., 0]), start, angle)
        best = np.where(inside, np.minimum(best, point_segment_distance(x, a, b)), best)
    # the segment's line cutting the circle: |a + s·u − c|² = ρ²
    w = a - c
    qa = u[..., 0] ** 2 + u[..., 1] ** 2
    qb = 2.0 * (u[..., 0] * w[..., 0] + u[..., 1] * w[..., 1])
    qc = w[..., 0] ** 2 + w[..., 1] ** 2 - rho ** 2
    disc = qb * qb - 4.0 * qa * qc
    root = np.sqrt(np.maximum(disc, 0.0))
    for sign in (1.0, -1.0):
        s = (-qb + sign * root) / np.where(nonzero, 2.0 * qa, 1.0)
        x = a + s[..., None] * u
        rx = x - c
        cut = nonzero & (disc >= 0) & (s >= 0) & (s <= 1) & _in_arc(np.arctan2(rx[..., 1], rx[..., 0]), start, angle)
        best = np.where(cut, 0.0, best)
    return best


def rotation_clearance(seg: Any, center: Any, angle: Any, other: Any) -> np.ndarray:
    """Least distance between the segment ``seg`` (``(..., 2, 2)``) turned about ``center``
    through ``angle`` (radians, signed) and the standing segment ``other`` — formula (1)
    of the module docstring (arrays broadcast over the leading axes).

    >>> round(float(rotation_clearance([[1, 0], [3, 0]], [0, 0], np.pi / 2, [[-1, 2.5], [1, 2.5]])), 12)
    0.0
    >>> round(float(rotation_clearance([[1, 0], [3, 0]], [0, 0], np.pi / 4, [[-1, 2.5], [1, 2.5]])), 6)
    1.06066
    """
    seg, other = np.asarray(seg, float), np.asarray(other, float)
    c, angle = np.asarray(center, float), np.asarray(angle, float)
    p, q, a, b = seg[..., 0, :], seg[..., 1, :], other[..., 0, :], other[..., 1, :]
    best = segment_distance(p, q, a, b)
    best = np.minimum(best, arc_segment_distance(c, p, angle, a, b))
    best = np.minimum(best, arc_segment_distance(c, q, angle, a, b))
    best = np.minimum(best, arc_segment_distance(c, a, -angle, p, q))
    return np.minimum(best, arc_segment_distance(c, b, -angle, p, q))
