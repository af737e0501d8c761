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

Most entries of a table are far from the threshold, and cheaper sound tests decide them
first (:func:`rotation_certain`; :func:`.batch.batch_swept` runs the same steps on
precomputed poses): a sampled pose nearer than ``bsum`` is a collision, and two bounds
prove the clearance: the *annulus* (:func:`annulus_clear`) and the *sampled bound*
(:func:`bisect_turns`).  A test decides only with :data:`MARGIN` to spare, far more than
the rounding of either computation, so it decides as the closed form would.

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.2 (point and
  segment), §5.3.2 (segment against circle, the intersection quadratic).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .segments import _psd, point_segment_distance, segment_distance

__all__ = ["MARGIN", "annulus_clear", "arc_segment_distance", "bisect_turns", "rotation_certain",
           "rotation_clearance", "turn_radii", "turn_slack"]

_TWO_PI = 2.0 * np.pi

#: how far (mm) a cheap test must clear ``bsum`` to decide an entry instead of the closed form:
#: many orders above the rounding of either computation (~1e-13 mm), so both decide alike
MARGIN = 1e-9


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


def turn_radii(seg: Any, center: Any) -> tuple[np.ndarray, np.ndarray]:
    """``(r_min, r_max)``: the least and greatest distance of a point of ``seg`` (``(..., 2, 2)``)
    from ``center`` — the centre's distance to the segment, and the farther end point's
    (distance from a point is convex along a segment).  A turn about ``center`` keeps them."""
    seg, c = np.asarray(seg, float), np.asarray(center, float)
    px, py, qx, qy = seg[..., 0, 0], seg[..., 0, 1], seg[..., 1, 0], seg[..., 1, 1]
    cx, cy = c[..., 0], c[..., 1]
    r_max = np.maximum(np.hypot(px - cx, py - cy), np.hypot(qx - cx, qy - cy))
    return _psd(cx, cy, px, py, qx, qy), r_max


def turn_slack(r_max: Any, angle: Any, parts: int = 1) -> np.ndarray:
    """``2·r_max·sin(|angle| / (4·parts))``: what the sampled bound (:func:`bisect_turns`) loses
    on a piece ``|angle| / parts`` of a turn (``|angle| ≤ 2π``)."""
    return 2.0 * np.asarray(r_max, float) * np.sin(np.abs(np.asarray(angle, float)) / (4.0 * parts))


def annulus_clear(center: Any, r_min: Any, r_max: Any, other: Any, bsum: Any) -> np.ndarray:
    """True where the standing segment ``other`` is certainly at least ``bsum`` from every pose of
    a segment turning about ``center`` with radii ``[r_min, r_max]`` (:func:`turn_radii`):
    ``dist(c, T) ≥ r_max + bsum`` or ``max_{y ∈ T} |y − c| ≤ r_min − bsum`` (with :data:`MARGIN`).

    Soundness: every point ``x`` of every pose has ``r_min ≤ |x − c| ≤ r_max``, so for ``y ∈ T``
    ``|x − y| ≥ |y − c| − |x − c| ≥ bsum`` in the first case and ``≥ |x − c| − |y − c| ≥ bsum`` in
    the second (the farthest point of ``T`` from ``c`` is an end point)."""
    c, other = np.asarray(center, float), np.asarray(other, float)
    cx, cy = c[..., 0], c[..., 1]
    ax, ay, bx, by = other[..., 0, 0], other[..., 0, 1], other[..., 1, 0], other[..., 1, 1]
    need = np.asarray(bsum, float) + MARGIN
    outside = _psd(cx, cy, ax, ay, bx, by) >= r_max + need
    far = np.maximum(np.hypot(ax - cx, ay - cy), np.hypot(bx - cx, by - cy))
    return outside | (far + need <= r_min)


def bisect_turns(d0: Any, d1: Any, slack: Any, bsum: Any, pose_distance: Any,
                 depth: int) -> tuple[np.ndarray, np.ndarray]:
    """Decide turns by sampling: ``(hit, open)`` boolean arrays over the entries.

    Entry ``e`` turns a segment ``S`` by ``Δ`` past a standing ``T``, with ``d0``, ``d1`` the
    distances of ``T`` from ``S(0)``, ``S(Δ)``, ``slack[e, l] = turn_slack(r_max, Δ, 2**l)``
    (``l = 0..depth``) and ``pose_distance(e, k)`` the distance of ``T`` from the pose
    ``S(k·Δ/2**depth)`` (entries ``e``, ``k`` arrays).  The turn is bisected ``depth`` times;
    a piece ``[φ_k, φ_k']`` (``h = |φ_k' − φ_k|``) is *clear* when::

        (d_k + d_k') / 2 − 2·r_max·sin(h/4) ≥ bsum + MARGIN

    Soundness: a point of ``S`` at radius ``r ≤ r_max`` moves ``2r·sin(t/2)`` in a turn by ``t``,
    so at ``φ`` in the piece the clearance is ``≥ d_k − 2r_max·sin(t/2)`` and ``≥ d_k' −
    2r_max·sin((h−t)/2)``; their mean is ``≥`` the bound, as ``sin`` is concave on ``[0, π]``.

    ``hit[e]``: a sampled pose is nearer than ``bsum − MARGIN`` (an actual collision).
    ``open[e]``: neither a hit nor every piece clear; the other entries are certainly free.
    """
    d0, d1 = np.asarray(d0, float), np.asarray(d1, float)
    slack = np.asarray(slack, float)
    bsum = np.broadcast_to(np.asarray(bsum, float), d0.shape)
    hit = np.zeros(len(d0), dtype=bool)
    # the open pieces: entry, left sample, distances at both ends
    ent = np.nonzero((d0 + d1) * 0.5 - slack[:, 0] < bsum + MARGIN)[0]
    lo, dl, dr = np.zeros(len(ent), dtype=np.int64), d0[ent], d1[ent]
    width = 2 ** depth
    for level in range(1, depth + 1):
        if not len(ent):
            break
        width //= 2
        dm = pose_distance(ent, lo + width)
        hit[ent[dm < bsum[ent] - MARGIN]] = True
        need, s = bsum[ent] + MARGIN, slack[ent, level]
        keep = np.concatenate([(dl + dm) * 0.5 - s < need, (dm + dr) * 0.5 - s < need])
        ent = np.concatenate([ent, ent])
        keep &= ~hit[ent]
        ent, lo = ent[keep], np.concatenate([lo, lo + width])[keep]
        dl, dr = np.concatenate([dl, dm])[keep], np.concatenate([dm, dr])[keep]
    open_ = np.zeros(len(d0), dtype=bool)
    open_[ent] = True
    return hit, open_ & ~hit


def rotation_certain(seg: Any, center: Any, angle: Any, other: Any, bsum: Any,
                     depth: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """``(free, hit)``: where the turn of :func:`rotation_clearance` (``|angle| ≤ 2π``) certainly
    keeps ``bsum`` from ``other`` (:func:`annulus_clear`, :func:`bisect_turns`), and where a pose
    certainly comes nearer; the closed form decides the rest (both false).  Arrays of any
    matching leading shape; what :func:`.batch.batch_swept` does with precomputed poses.

    >>> seg, other = [[1, 0], [3, 0]], [[-1, 2.5], [1, 2.5]]
    >>> [bool(v) for v in rotation_certain(seg, [0, 0], np.pi / 2, other, 0.5)]   # clearance 0
    [False, True]
    >>> [bool(v) for v in rotation_certain(seg, [0, 0], np.pi / 8, other, 0.5)]   # clearance > 1.9
    [True, False]
    """
    seg, other = np.asarray(seg, float), np.asarray(other, float)
    c, angle = np.asarray(center, float), np.asarray(angle, float)
    shape = np.broadcast_shapes(seg.shape[:-2], other.shape[:-2], c.shape[:-1], angle.shape, np.shape(bsum))
    seg, other = (np.broadcast_to(v, shape + (2, 2)).reshape(-1, 2, 2) for v in (seg, other))
    c, angle = np.broadcast_to(c, shape + (2,)).reshape(-1, 2), np.broadcast_to(angle, shape).reshape(-1)
    bsum = np.broadcast_to(np.asarray(bsum, float), shape).reshape(-1)
    width = 2 ** depth

    def pose_distance(e: np.ndarray, k: np.ndarray) -> np.ndarray:
        turn = angle[e] * (k / width)
        p, q = _rotate(seg[e, 0], c[e], turn), _rotate(seg[e, 1], c[e], turn)
        return segment_distance(p, q, other[e, 0], other[e, 1])

    all_ = np.arange(len(bsum))
    d0 = segment_distance(seg[:, 0], seg[:, 1], other[:, 0], other[:, 1])
    d1 = pose_distance(all_, np.full(len(all_), width))
    r_min, r_max = turn_radii(seg, c)
    slack = np.stack([turn_slack(r_max, angle, 2 ** level) for level in range(depth + 1)], axis=-1)
    hit, open_ = bisect_turns(d0, d1, slack, bsum, pose_distance, depth)
    hit |= np.minimum(d0, d1) < bsum - MARGIN
    free = ~hit & (~open_ | annulus_clear(c, r_min, r_max, other, bsum))
    return free.reshape(shape), hit.reshape(shape)
