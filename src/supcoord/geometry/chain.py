"""The colliding segment of a robot as a planar two-link chain (one formula for every robot kind).

A robot's colliding segment is the end of a chain of two links turning about the base:
the elbow at ``e = l1·(cos a, sin a)`` and the segment's end points ``e + R(a + b)·s_k``,
``s_k`` given in the second link's frame (origin at the elbow, +x at ``a + b``).  The
alpha-beta robot is the chain itself (``l1 = alpha``, ``a = α + α₀``, ``b = β + β₀``); the
seed paper's rotary arm is its second link alone (``l1 = 0``, ``a = 0``, ``b = θ``).

:func:`chain_segments` evaluates it on arrays (each entry its own link lengths and
segment), :func:`chain_angles_deg` turns joint angles in degrees into the chain's angles.
:mod:`.chain_motion` repeats the formula on Python floats for one motion at a time.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["chain_segments", "chain_angles_deg"]


def chain_segments(l1: Any, segment: Any, a: Any, b: Any) -> np.ndarray:
    """Colliding segments ``(..., 2, 2)`` relative to the base of chains with first links ``l1``
    ``(...)``, segments ``(..., 2, 2)`` in the second link's frame, at angles ``a``, ``b``
    (radians, ``(...)``); every argument broadcasts against the others."""
    a, b, l1 = np.asarray(a, float), np.asarray(b, float), np.asarray(l1, float)
    s = np.asarray(segment, float)
    ex, ey = (l1 * np.cos(a))[..., None], (l1 * np.sin(a))[..., None]
    c, sn = np.cos(a + b)[..., None], np.sin(a + b)[..., None]
    x = ex + (s[..., 0] * c - s[..., 1] * sn)
    y = ey + (s[..., 0] * sn + s[..., 1] * c)
    return np.stack([x, y], axis=-1)


def chain_angles_deg(angles_deg: Any, offsets_deg: Any) -> tuple[np.ndarray, np.ndarray]:
    """The chain's angles ``(a, b)`` (radians) of joint angles ``(..., J)`` in degrees, each
    joint turned by its calibration offset ``offsets_deg`` ``(..., J)``: two joints drive
    ``a`` and ``b``; a single joint drives ``b`` (``a = 0``)."""
    angles = np.radians(np.asarray(angles_deg, float) + np.asarray(offsets_deg, float))
    if angles.shape[-1] == 1:
        return np.zeros(angles.shape[:-1]), angles[..., 0]
    return angles[..., 0], angles[..., 1]
