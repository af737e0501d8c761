"""Fixed obstacles and robots held in place: per-robot *unary* tables.

A fixed obstacle ``O`` (a fiducial, a guide camera, an offline robot's arm: a segment in the
focal plane, a point being a zero-length one) with buffer ``r_O`` collides with robot
``p`` when ``dist(S_p, O) < r_p + r_O`` — the pair rule of :mod:`.collision` with a partner
that never moves.  For each robot near obstacles:

- static table ``U[i]``: ``p`` at position ``i`` collides with some obstacle;
- swept table ``V[m, i]``: the single-joint move ``m`` from ``i`` collides with some
  obstacle somewhere along the turn (exact: :func:`.collision.swept_table` against a
  :class:`FixedSegment`), or leaves the hard stops, or starts or ends in ``U``.

A robot *held in place* at position ``f`` has ``U[i] = (i ≠ f)`` and every move blocked.

:class:`~.collision.CollisionTables` folds these into the pair tables of the robot's
neighbour pairs (``T[i, j] ∨ U_a[i] ∨ U_b[j]``), so every consumer of the pair tables (the
guards of the symbolic model, windows, descent) honours them without knowing they exist;
motions of several joints at once are checked by :func:`obstacle_motion_collides`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .chain_motion import ChainGeometry, chain_geometry, chain_motion_collides
from .joint_space import Joint, Kinematics
from .motion import DEFAULT_TOL, motion_collides
from .segments import segment_distance

__all__ = ["FixedSegment", "UnaryTables", "near_obstacles", "unary_tables", "held_tables", "rule_tables",
           "obstacle_motion_collides"]


class FixedSegment(Kinematics):
    """A segment that never moves (one position; coordinates relative to base ``(0, 0)``)."""

    kind = "fixed"

    def __init__(self, segment: Any):
        self.segment = np.asarray(segment, dtype=float).reshape(2, 2)
        self.joints = (Joint("fixed", 1, False),)

    @property
    def reach(self) -> float:
        return float(np.hypot(self.segment[:, 0], self.segment[:, 1]).max())

    def segments(self, q: Any) -> np.ndarray:
        q = np.asarray(q)
        return np.broadcast_to(self.segment, q.shape[:-1] + (2, 2)).copy()

    def sweep_length(self, delta: Any) -> np.ndarray:
        return np.zeros(np.asarray(delta).shape[:-1])

    def chain(self) -> tuple[float, tuple[tuple[float, float], tuple[float, float]]]:
        (x0, y0), (x1, y1) = self.segment.tolist()
        return 0.0, ((x0, y0), (x1, y1))

    def chain_angles(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        zero = np.zeros(np.asarray(q).shape[:-1])
        return zero, zero

    def chain_offsets_deg(self) -> tuple[float, ...]:
        return (0.0,)

    def key(self) -> tuple:
        return ("fixed", tuple(self.segment.ravel().tolist()))

    def to_json(self) -> dict:
        return {"kind": "fixed", "segment": self.segment.tolist()}


#: ``(U, V)`` of one robot: static ``(n_positions,)`` and swept ``(n_moves, n_positions)`` booleans
UnaryTables = tuple[np.ndarray, np.ndarray]


def near_obstacles(base: Any, reach: float, buffer: float, obstacles: np.ndarray, buffers: np.ndarray) -> np.ndarray:
    """Indices of the obstacles a robot can touch: ``dist(base, O) < reach + r_p + r_O``."""
    if not len(obstacles):
        return np.zeros(0, dtype=int)
    b = np.broadcast_to(np.asarray(base, float), (len(obstacles), 2))
    d = segment_distance(b, b, obstacles[:, 0], obstacles[:, 1])
    return np.nonzero(d < reach + buffer + buffers)[0]


def unary_tables(kin: Kinematics, base: Any, buffer: float, obstacles: np.ndarray,
                 buffers: np.ndarray) -> UnaryTables | None:
    """``(U, V)`` of a robot against the ``obstacles`` it can touch (module docstring), or
    ``None`` when it can touch none."""
    from .collision import distance_table, swept_table  # collision imports this module

    near = near_obstacles(base, kin.reach, buffer, obstacles, buffers)
    if not len(near):
        return None
    U = np.zeros(kin.n_positions, dtype=bool)
    V = np.zeros((len(kin.moves()), kin.n_positions), dtype=bool)
    for o in near:
        fixed = FixedSegment(obstacles[o])
        bsum = float(buffer + buffers[o])
        dist = distance_table(kin, base, (0.0, 0.0), fixed)
        U |= dist[:, 0] < bsum
        V |= swept_table(kin, base, (0.0, 0.0), bsum, 0, kin_b=fixed, distances=dist)[:, :, 0]
    return U, V


def held_tables(kin: Kinematics, position: Any) -> UnaryTables:
    """``(U, V)`` of a robot held at ``position``: every other position and every move refused."""
    U = np.ones(kin.n_positions, dtype=bool)
    U[int(kin.flat_index(np.asarray(position)))] = False
    return U, np.ones((len(kin.moves()), kin.n_positions), dtype=bool)


def rule_tables(kin: Kinematics, c0: float, c1: float) -> UnaryTables:
    """``(U, V)`` of the joint rule "``β < c0 + c1·α`` is forbidden" (commanded degrees).  The
    allowed set is a half-plane of joint space and a move is linear in the angles, so a move
    stays allowed iff both its ends are."""
    pos = kin.all_positions()
    ang = kin.joint_angles_deg(pos)
    U = ang[:, 1] < c0 + c1 * ang[:, 0]
    V = np.ones((len(kin.moves()), len(pos)), dtype=bool)
    for m, (joint, d) in enumerate(kin.moves()):
        nxt, ok = kin.step_array(pos, joint, d)
        V[m, ok] = U[ok] | U[kin.flat_index(nxt[ok])]
    return U, V


def _fixed_chain(segment: np.ndarray) -> ChainGeometry:
    """The :class:`ChainGeometry` of a fixed segment, made once per segment (held with its
    :class:`FixedSegment`, which the geometry refers to weakly)."""
    key = tuple(np.asarray(segment, float).ravel().tolist())
    held = _FIXED_CHAINS.get(key)
    if held is None:
        if len(_FIXED_CHAINS) > 4096:
            _FIXED_CHAINS.clear()
        fixed = FixedSegment(segment)
        held = _FIXED_CHAINS[key] = (fixed, chain_geometry(fixed))
    return held[1]


_FIXED_CHAINS: dict[tuple, tuple[FixedSegment, ChainGeometry]] = {}


def obstacle_motion_collides(kin: Kinematics, base: Any, q0: Any, delta: Any, buffer: float, obstacles: np.ndarray,
                             buffers: np.ndarray, tol: float = DEFAULT_TOL) -> np.ndarray:
    """Does the motion ``q0 + t·delta`` (``(E, J)``, several joints at once) of a robot collide
    with one of ``obstacles``?  Certified as :func:`.motion.motion_collides` (conservative by
    at most ``tol``); a single motion by :func:`.chain_motion.chain_motion_collides`, the same
    certificate on floats."""
    q0 = np.atleast_2d(np.asarray(q0, float))
    delta = np.broadcast_to(np.asarray(delta, float), q0.shape)
    hit = np.zeros(len(q0), dtype=bool)
    near = near_obstacles(base, kin.reach, buffer, obstacles, buffers)
    if len(q0) == 1 and np.all(np.abs(delta) <= 1):  # one motion (the planners' queries): on floats
        geo, start, d = chain_geometry(kin), q0[0].astype(int), delta[0].astype(int)
        hit[0] = any(chain_motion_collides(geo, base, start, d, _fixed_chain(obstacles[o]), (0.0, 0.0),
                                           (0,), (0,), float(buffer + buffers[o]), tol) for o in near)
        return hit
    for o in near:
        fixed = FixedSegment(obstacles[o])
        still = np.zeros((len(q0), 1))
        hit |= motion_collides(kin, base, q0, delta, fixed, (0.0, 0.0), still, still, float(buffer + buffers[o]), tol)
    return hit
