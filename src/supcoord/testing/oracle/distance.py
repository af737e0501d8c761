"""Segment–segment distance as the distance from the origin to a Minkowski difference.

For segments ``P = {p0 + s·u : s ∈ [0, 1]}`` and ``Q = {q0 + t·w : t ∈ [0, 1]}`` in the
plane (complex numbers, ``u = p1 − p0``, ``w = q1 − q0``)::

    dist(P, Q) = min_{s,t ∈ [0,1]} |p(s) − q(t)| = dist(0, M),
    M = P ⊖ Q = {c + s·u + t·v : s, t ∈ [0, 1]},   c = p0 − q0,  v = −w

``M`` is a parallelogram (a segment when ``u ∥ w``).  The origin is inside it iff
``s·u + t·v = −c`` has a solution in ``[0, 1]²`` (Cramer's rule with the cross product
``u × v = Im(ū·v)``, when ``u × v ≠ 0``): then the segments meet at ``p(s) = q(t)``.
Otherwise the closest point of the convex set ``M`` lies on its boundary, the four edges
``c + [0,1]·u``, ``c + v + [0,1]·u``, ``c + [0,1]·v``, ``c + u + [0,1]·v``; the distance
from the origin to an edge ``[e, e + f]`` is ``|e + λ·f|`` with
``λ = clamp(−Re(ē·f)/|f|², 0, 1)``.  (A parallel pair has ``u × v = 0``: ``M`` is then
flat, and its edges are all of it.)  Each candidate is evaluated as the distance of two
actual points of the segments — the interior one as ``|p(s) − q(t)|`` with ``(s, t)``
clamped to ``[0, 1]²`` rather than as 0 — so that a nearly parallel pair, whose Cramer
solution is rounding noise, can never read as meeting.

This is the convex-set formulation of GJK — a different algorithm from the project's
crossing test (:mod:`supcoord.geometry.segments`) and from the validator's clamped
closest points (Ericson); :mod:`supcoord.testing.oracle` imports neither.

>>> float(segment_gap(0j, 2 + 0j, 1 + 1j, 1 + 3j))
1.0
>>> float(segment_gap(0j, 2 + 2j, 2j, 2 + 0j))   # crossing
0.0

References
----------
- E. G. Gilbert, D. W. Johnson, S. S. Keerthi, A fast procedure for computing the distance
  between complex objects in three-dimensional space, IEEE J. Robotics and Automation 4(2), 1988.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["origin_to_edge", "segment_gap"]


def _cross(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return x.real * y.imag - x.imag * y.real


def origin_to_edge(e: Any, f: Any) -> np.ndarray:
    """Distance from 0 to the segments ``[e, e + f]`` (complex arrays, broadcast)."""
    e, f = np.asarray(e, dtype=complex), np.asarray(f, dtype=complex)
    ff = f.real * f.real + f.imag * f.imag
    lam = -(e.real * f.real + e.imag * f.imag) / np.where(ff > 0, ff, 1.0)
    lam = np.minimum(np.maximum(lam, 0.0), 1.0)
    return np.abs(e + lam * f)


def segment_gap(p0: Any, p1: Any, q0: Any, q1: Any) -> np.ndarray:
    """Distance between the segments ``[p0, p1]`` and ``[q0, q1]`` (complex arrays, broadcast)."""
    p0, p1, q0, q1 = (np.asarray(x, dtype=complex) for x in (p0, p1, q0, q1))
    c, u, v = p0 - q0, p1 - p0, q0 - q1
    det = _cross(u, v)
    safe = np.where(det != 0, det, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):  # nearly parallel: noise, clamped below
        s = np.nan_to_num(np.clip(_cross(-c, v) / safe, 0.0, 1.0))
        t = np.nan_to_num(np.clip(_cross(u, -c) / safe, 0.0, 1.0))
    inner = np.where(det != 0, np.abs((p0 + s * u) - (q0 - t * v)), np.inf)
    d = np.minimum(np.minimum(origin_to_edge(c, u), origin_to_edge(c + v, u)),
                   np.minimum(origin_to_edge(c, v), origin_to_edge(c + u, v)))
    return np.minimum(d, inner)
