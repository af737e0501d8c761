"""Robots that each have their own kinematics: reaches, segments and motions, grouped by geometry.

A layout's robots share one :class:`~.joint_space.Kinematics` (a uniform grid of identical
robots) or each has its own (its own lattice holding its exact start and target, its
measured arms): every function here takes either, and groups robots with equal
:meth:`~.joint_space.Kinematics.key` so identical robots are computed together.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .joint_space import Kinematics
from .motion import DEFAULT_TOL, motion_collides, placed_segments

__all__ = ["robot_reaches", "intern_kinematics", "robot_segments", "robots_motion_collides", "chain_arrays"]


def robot_reaches(kin: Kinematics | list[Kinematics], n: int) -> np.ndarray:
    """Per robot, :attr:`Kinematics.reach` (``kin`` shared or one per robot)."""
    if isinstance(kin, Kinematics):
        return np.full(n, kin.reach)
    return np.array([k.reach for k in kin], dtype=float)


def intern_kinematics(kins: list[Kinematics] | None, n: int) -> tuple[list[Kinematics] | None, np.ndarray]:
    """``(distinct, ids)``: each robot's kinematics as an index into the distinct ones (equal
    :meth:`Kinematics.key`), so identical robots share tables; ``(None, zeros)`` without ``kins``."""
    if kins is None:
        return None, np.zeros(n, dtype=np.int64)
    for held, result in _INTERNED:  # a problem's list is interned once, not at every motion check
        if held is kins and len(result[1]) == n:
            return result[0], result[1].copy()
    seen: dict[tuple, int] = {}
    distinct: list[Kinematics] = []
    ids = np.empty(n, dtype=np.int64)
    for p, k in enumerate(kins):
        key = k.key()
        if key not in seen:
            seen[key] = len(distinct)
            distinct.append(k)
        ids[p] = seen[key]
    _INTERNED.insert(0, (kins, (distinct, ids.copy())))
    del _INTERNED[4:]
    return distinct, ids


#: the last few lists interned (held, so that an identity match is the same list)
_INTERNED: list[tuple[list, tuple[list, np.ndarray]]] = []


def robot_segments(kin: Kinematics | list[Kinematics], bases: Any, positions: Any) -> np.ndarray:
    """Colliding segments in the focal plane of robots at (fractional) ``positions``
    ``(..., N, J)``: ``(..., N, 2, 2)``; ``kin`` shared or one per robot (grouped by key)."""
    if isinstance(kin, Kinematics):
        return placed_segments(kin, bases, positions)
    bases = np.asarray(bases, float)
    q = np.asarray(positions)
    distinct, ids = intern_kinematics(kin, len(bases))
    out = np.empty(q.shape[:-1] + (2, 2))
    for u, k in enumerate(distinct):
        idx = np.nonzero(ids == u)[0]
        out[..., idx, :, :] = placed_segments(k, bases[idx], q[..., idx, :])
    return out


def robots_motion_collides(kin: Kinematics | list[Kinematics], a: Any, base_a: Any, qa: Any, da: Any,
                           b: Any, base_b: Any, qb: Any, db: Any, bsum: Any, tol: float = DEFAULT_TOL) -> np.ndarray:
    """:func:`motion_collides` for entries of robots ``a[e]`` and ``b[e]`` (``(E,)`` ints; the
    other arrays ``(E, …)``), each with its own kinematics (``kin`` shared or one per robot)."""
    if isinstance(kin, Kinematics):
        return motion_collides(kin, base_a, qa, da, kin, base_b, qb, db, bsum, tol)
    a, b = np.atleast_1d(np.asarray(a)), np.atleast_1d(np.asarray(b))
    e = np.broadcast_shapes(a.shape, b.shape)
    a, b = np.broadcast_to(a, e), np.broadcast_to(b, e)
    arrays = [np.broadcast_to(np.asarray(x, float), e + np.shape(x)[-1:]) for x in (base_a, qa, da, base_b, qb, db)]
    bsum = np.broadcast_to(np.asarray(bsum, float), e)
    distinct, ids = intern_kinematics(kin, len(kin))
    groups: dict[tuple[int, int], list[int]] = {}
    for i, (x, y) in enumerate(zip(ids[a].tolist(), ids[b].tolist())):
        groups.setdefault((x, y), []).append(i)
    out = np.zeros(e, dtype=bool)
    for (x, y), sel in groups.items():
        ba, pa, ea, bb, pb, eb = (v[sel] for v in arrays)
        out[sel] = motion_collides(distinct[x], ba, pa, ea, distinct[y], bb, pb, eb, bsum[sel], tol)
    return out


def chain_arrays(kins: list[Kinematics]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(l1, segment, offsets)``: per robot its chain (:meth:`Kinematics.chain`: ``(N,)``,
    ``(N, 2, 2)``) and joint offsets (:meth:`Kinematics.chain_offsets_deg`, ``(N, J)``), so
    that :func:`.chain.chain_segments` evaluates robots that each have their own arms at once."""
    chains = [k.chain() for k in kins]
    l1 = np.array([c[0] for c in chains], dtype=float)
    seg = np.array([c[1] for c in chains], dtype=float).reshape(len(kins), 2, 2)
    offsets = np.array([k.chain_offsets_deg() for k in kins], dtype=float).reshape(len(kins), -1)
    return l1, seg, offsets
