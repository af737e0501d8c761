"""The colliding segment of a robot as a planar two-link chain (one formula for every robot kind).

A robot's colliding segment is the end of a chain of two links turning about the base:
the elbow at ``e = l1·(cos a, sin a)`` and the segment's end points ``e + R(a + b)·s_k``,
``s_k`` given in the second link's frame (origin at the elbow, +x at ``a + b``).  The
alpha-beta robot is the chain itself (``l1 = alpha``, ``a = α + α₀``, ``b = β + β₀``); the
seed paper's rotary arm is its second link alone (``l1 = 0``, ``a = 0``, ``b = θ``).

:func:`chain_segments` evaluates it on arrays (each entry its own link lengths and
segment; :func:`chain_segment_rows`: the same as coordinate arrays), :func:`chain_angles_deg` turns joint angles in degrees into the chain's angles.
:mod:`.chain_motion` repeats the formula on Python floats for one motion at a time.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["chain_segments", "chain_segment_rows", "chain_angles_deg"]


def chain_segments(l1: Any, segment: Any, a: Any, b: Any) -> np.ndarray:
    """Colliding segments ``(..., 2, 2)`` relative to the base of chains with first links ``l1``
    ``(...)``, segments ``(..., 2, 2)`` in the second link's frame, at angles ``a``, ``b``
    (radians, ``(...)``); every argument broadcasts against the others."""
    rows = chain_segment_rows(l1, segment, a, b)
    out = np.empty(np.broadcast_shapes(*(r.shape for r in rows)) + (2, 2))
    out[..., 0, 0], out[..., 0, 1], out[..., 1, 0], out[..., 1, 1] = rows
    return out


def chain_segment_rows(l1: Any, segment: Any, a: Any, b: Any) -> tuple[np.ndarray, ...]:
    """:func:`chain_segments` as four coordinate arrays ``(px, py, qx, qy)`` (mm, relative to
    the base): each coordinate of each end point on its own contiguous array, the layout of
    :func:`.segments.segment_distance_xy` (interleaved ``(..., 2, 2)`` arrays make numpy loop
    two elements at a time)."""
    a, b, l1 = np.asarray(a, float), np.asarray(b, float), np.asarray(l1, float)
    s = np.asarray(segment, float)
    ex, ey = l1 * np.cos(a), l1 * np.sin(a)
    ab = a + b
    c, sn = np.cos(ab), np.sin(ab)
    rows = []
    for k in (0, 1):
        sx, sy = s[..., k, 0], s[..., k, 1]
        rows += [ex + (sx * c - sy * sn), ey + (sx * sn + sy * c)]
    return tuple(rows)


def chain_angles_deg(angles_deg: Any, offsets_deg: Any) -> tuple[np.ndarray, np.ndarray]:
    """The chain's angles ``(a, b)`` (radians) of joint angles ``(..., J)`` in degrees, each
    joint turned by its calibration offset ``offsets_deg`` ``(..., J)``: two joints drive
    ``a`` and ``b``; a single joint drives ``b`` (``a = 0``)."""
    angles = np.radians(np.asarray(angles_deg, float) + np.asarray(offsets_deg, float))
    if angles.shape[-1] == 1:
        return np.zeros(angles.shape[:-1]), angles[..., 0]
    return angles[..., 0], angles[..., 1]
