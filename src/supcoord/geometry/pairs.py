"""Which robots of a layout can collide, and which collide at given positions.

- Neighbour pairs: ``{(a, b) : a < b, |x_a − x_b| < reach_a + reach_b + r_a + r_b}``
  (only these can ever collide: each robot's colliding segment stays within its reach).
- Colliding pairs at positions ``q``: ``dist(S_a(q_a), S_b(q_b)) < r_a + r_b``
  (:mod:`.collision`'s definition, strict).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .fleet import robot_reaches, robot_segments
from .kinematics import Kinematics
from .segments import segment_distance

__all__ = ["neighbour_pairs", "colliding_pairs"]


def neighbour_pairs(bases: Any, reach: Any, buffers: Any) -> np.ndarray:
    """Pairs ``(a, b)``, ``a < b``, whose reach discs grown by the buffers overlap: ``(P, 2)`` ints.

    ``|x_a − x_b| < reach_a + reach_b + r_a + r_b``, sorted lexicographically.  The candidates
    are the pairs a k-d tree finds within twice the largest grown reach
    (:meth:`scipy.spatial.cKDTree.query_pairs`, with room for its rounding); each is then
    decided by the formula above, so the time and memory grow with the pairs, not ``N²``.

    >>> neighbour_pairs([[0, 0], [9, 0], [30, 0]], 4.0, 1.0).tolist()
    [[0, 1]]
    """
    xy = np.asarray(bases, float).reshape(-1, 2)
    n = len(xy)
    reach = np.broadcast_to(np.asarray(reach, float), (n,))
    buffers = np.broadcast_to(np.asarray(buffers, float), (n,))
    grow = reach + buffers
    if n < 2:
        return np.zeros((0, 2), dtype=int)
    radius = 2 * float(grow.max()) * (1 + 1e-9) + 1e-9
    from scipy.spatial import cKDTree  # imported here: 0.4 s of start-up that the commands
    # which never search for neighbours (paper, supcon, force, their study cases) need not pay

    pairs = cKDTree(xy).query_pairs(radius, output_type="ndarray").astype(int).reshape(-1, 2)
    pairs.sort(axis=1)
    a, b = pairs[:, 0], pairs[:, 1]
    d = np.linalg.norm(xy[a, None, :] - xy[b, None, :], axis=-1)[:, 0]
    pairs = pairs[d < grow[a] + grow[b]]
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def colliding_pairs(kin: Kinematics | list[Kinematics], bases: Any, buffers: Any, positions: Any,
                    pairs: Any | None = None) -> list[tuple[int, int, float]]:
    """Pairs ``(a, b, distance)`` that collide statically at ``positions`` (``(N, J)`` ints);
    ``kin`` is shared by every robot or a list with each robot's own."""
    bases = np.asarray(bases, float)
    buffers = np.broadcast_to(np.asarray(buffers, float), (len(bases),))
    if pairs is None:
        pairs = neighbour_pairs(bases, robot_reaches(kin, len(bases)), buffers)
    pairs = np.asarray(pairs, int).reshape(-1, 2)
    seg = robot_segments(kin, bases, np.asarray(positions))
    a, b = pairs[:, 0], pairs[:, 1]
    d = segment_distance(seg[a, 0], seg[a, 1], seg[b, 0], seg[b, 1])
    bad = d < buffers[a] + buffers[b]
    return [(int(i), int(j), float(x)) for i, j, x in zip(a[bad], b[bad], d[bad])]
