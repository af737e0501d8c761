"""The discretised joint space of a positioner: joints, positions, single moves.

A position is a tuple of joint indices ``q = (q_0, …, q_{J-1})``, ``q_j ∈ {0, …,
steps_j − 1}``; a *move* changes one joint by ``±1``, cyclically where the joint wraps,
never past a hard stop otherwise::

    N(q) = {q + δ·e_j : j < J, δ ∈ {−1, +1}, (q + δ·e_j)_j ∈ [0, steps_j) or joint j wraps}

:class:`Kinematics` holds the index arithmetic shared by every kinematics and declares
the geometry each one defines (:mod:`.kinematics`: the rotary arm of the seed paper and
the alpha-beta robot).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from .layout import _short

__all__ = ["Joint", "Kinematics", "MAX_LENGTH", "MAX_POSITIONS"]

#: longest arm accepted (mm); anything longer is a unit mistake
MAX_LENGTH = 1e6
#: most positions of one positioner: a pair's collision tables hold positions² entries, and
#: :data:`supcoord.geometry.collision.MAX_TABLE_ENTRIES` is ``MAX_POSITIONS²`` (5·10⁷)
MAX_POSITIONS = 7071


@dataclass(frozen=True)
class Joint:
    """One discretised joint: its name, number of positions, and whether it wraps."""

    name: str
    steps: int
    wraps: bool


class Kinematics:
    """Common interface of the discretised kinematics (see the module docstring)."""

    kind: str = ""
    joints: tuple[Joint, ...] = ()

    # --- index spaces -------------------------------------------------------------
    @property
    def n_joints(self) -> int:
        return len(self.joints)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(j.steps for j in self.joints)

    @property
    def n_positions(self) -> int:
        """Number of discrete positions of one positioner (product of the joints' steps)."""
        return int(np.prod(self.shape))

    def all_positions(self) -> np.ndarray:
        """Every position as an ``(n_positions, J)`` int array, in :meth:`flat_index` order."""
        grids = np.meshgrid(*[np.arange(s) for s in self.shape], indexing="ij")
        return np.stack([g.ravel() for g in grids], axis=-1)

    def flat_index(self, q: Any) -> np.ndarray:
        """Row-major index of positions ``q`` (``(..., J)`` ints) in :meth:`all_positions`."""
        q = np.asarray(q)
        return np.ravel_multi_index(tuple(np.moveaxis(q, -1, 0)), self.shape)

    def flat_position(self, q: Any) -> int:
        """:meth:`flat_index` of one position ``q`` (``(J,)`` ints inside the ranges), without checks (fast path)."""
        return int(np.dot(q, self._strides))

    def in_range(self, q: Any) -> np.ndarray:
        q = np.asarray(q)
        return np.all((q >= 0) & (q < self._steps), axis=-1)

    # --- moves --------------------------------------------------------------------
    def moves(self) -> list[tuple[int, int]]:
        """The single-joint moves ``(joint, delta)``, ``delta ∈ {+1, −1}``, in a fixed order."""
        return [(j, d) for j in range(self.n_joints) for d in (+1, -1)]

    def reversed_moves(self) -> dict[int, int]:
        """``{r: m}``: move ``r`` is move ``m`` run backwards (same joint, opposite step, ``m < r``).

        Move ``r`` from position ``i`` is inside the stops exactly when ``i = step(m, i0)`` for
        some ``i0``, and then it travels the joint-space segment of ``m`` from ``i0`` the other
        way: the same poses, so the same swept collisions (``W_r[step_m(i0), j] = W_m[i0, j]``)."""
        index = {mv: n for n, mv in enumerate(self.moves())}
        return {index[(j, d)]: index[(j, -d)] for j, d in self.moves() if d < 0}

    def step(self, q: Any, joint: int, delta: int) -> np.ndarray | None:
        """The position after one move, or ``None`` past a hard stop."""
        out, ok = self.step_array(q, joint, delta)
        return out if ok else None

    def step_array(self, q: Any, joint: int, delta: int) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`step` over positions ``q`` ``(..., J)``: ``(next, ok)``, ``ok`` False past a hard stop
        (where ``next`` holds the index beyond it); only the moved joint is wrapped."""
        out = np.array(q, dtype=int)
        jt = self.joints[joint]
        nxt = out[..., joint] + delta
        if jt.wraps:
            nxt %= jt.steps
            ok = np.ones(out.shape[:-1], dtype=bool)
        else:
            ok = (nxt >= 0) & (nxt < jt.steps)
        out[..., joint] = nxt
        return out, ok

    def step_valid(self, q: Any, joint: int, delta: int) -> np.ndarray:
        """Boolean mask over positions ``q`` (``(..., J)``): is the move inside the hard stops?"""
        return self.step_array(q, joint, delta)[1]

    def wrap(self, q: Any) -> np.ndarray:
        """Positions ``q`` ``(..., J)`` with every wrapping joint taken modulo its steps (``q + Δ`` → a position)."""
        q = np.asarray(q)
        return np.where(self._wraps, q % self._steps, q)

    def neighbours(self, q: Any) -> list[np.ndarray]:
        """Positions one move away from ``q`` (wrapping joints wrap, others stop)."""
        out = []
        for j, d in self.moves():
            nxt = self.step(q, j, d)
            if nxt is not None and not np.array_equal(nxt, q):
                out.append(nxt)
        return out

    def joint_distance(self, a: Any, b: Any) -> np.ndarray:
        """Per-joint number of single steps from ``a`` to ``b`` (cyclic where the joint wraps)."""
        a, b = np.asarray(a), np.asarray(b)
        diff = np.abs(a - b)
        steps = self._steps
        return np.where(self._wraps, np.minimum(diff, steps - diff), diff)

    def signed_delta(self, a: Any, b: Any) -> np.ndarray:
        """The per-joint step ``b − a`` taken the short way round for wrapping joints.

        For consecutive plan configurations each entry is in ``{−1, 0, +1}`` when the
        plan is well formed (a wrapping joint with 2 steps counts as ``+1``).
        """
        a, b = np.asarray(a), np.asarray(b)
        d = b - a
        steps = self._steps
        wrapped = (d + steps // 2) % steps - steps // 2
        wrapped = np.where((steps == 2) & (wrapped == -1), 1, wrapped)
        return np.where(self._wraps, wrapped, d)

    def directions(self, a: Any, b: Any) -> list[tuple[int, ...]]:
        """Per joint, the deltas of the single moves that bring position ``a`` nearer to ``b`` the
        short way round: ``()`` where they agree, ``(+1, −1)`` at half a turn of a wrapping joint."""
        out: list[tuple[int, ...]] = []
        for jt, d in zip(self.joints, self.signed_delta(a, b).tolist()):
            if d == 0:
                out.append(())
            elif jt.wraps and 2 * abs(d) == jt.steps:
                out.append((+1, -1))
            else:
                out.append((+1,) if d > 0 else (-1,))
        return out

    @cached_property
    def _steps(self) -> np.ndarray:
        return np.array(self.shape)

    @cached_property
    def _strides(self) -> np.ndarray:
        return np.array([int(np.prod(self.shape[j + 1:])) for j in range(len(self.shape))])

    @cached_property
    def _wraps(self) -> np.ndarray:
        return np.array([j.wraps for j in self.joints])

    # --- geometry (overridden) ----------------------------------------------------
    @property
    def reach(self) -> float:
        """An upper bound on the distance from the base of any point of the colliding segment."""
        raise NotImplementedError

    def segments(self, q: Any) -> np.ndarray:
        """Colliding segment relative to the base, ``(..., 2, 2)`` (start, end) for ``q`` ``(..., J)`` floats."""
        raise NotImplementedError

    def sweep_length(self, delta: Any) -> np.ndarray:
        """Bound on the path length of any point of the colliding segment for ``q → q + delta``."""
        raise NotImplementedError

    def rotation(self, q: Any, joint: int, delta: Any) -> tuple[np.ndarray, np.ndarray]:
        """A single-joint move as a rigid turn of the colliding segment: ``(centre, angle)``.

        For positions ``q`` (``(..., J)``) and steps ``delta`` of ``joint``, the segment of
        ``q + t·delta·e_joint`` is the segment of ``q`` turned by ``t·angle`` (radians,
        counter-clockwise positive) about ``centre`` (``(..., 2)``, relative to the base).
        """
        raise NotImplementedError

    def chain(self) -> tuple[float, tuple[tuple[float, float], tuple[float, float]]]:
        """The colliding segment as a planar two-link chain: ``(l1, ((x0, y0), (x1, y1)))``, the
        elbow at ``l1·(cos a, sin a)`` from the base and the segment's end points given in the
        second link's frame (origin at the elbow, +x at ``a + b``); the angles ``(a, b)`` of a
        position are :meth:`chain_angles`.  :meth:`segments` is this chain at those angles."""
        raise NotImplementedError

    def chain_angles(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        """The chain's angles ``(a, b)`` (radians) of (fractional) positions ``q`` (:meth:`chain`)."""
        raise NotImplementedError

    def chain_offsets_deg(self) -> tuple[float, ...]:
        """Per joint, the calibration offset (degrees) between the commanded angle and the chain's
        (:func:`.chain.chain_angles_deg`)."""
        raise NotImplementedError

    def fibre(self, q: Any) -> np.ndarray:
        return self.segments(q)[..., 1, :]

    def joint_angles_deg(self, q: Any) -> np.ndarray:
        """Joint angles in degrees ``(..., J)`` of (fractional) positions ``q``."""
        raise NotImplementedError

    def segments_at_deg(self, angles_deg: Any) -> np.ndarray:
        """Colliding segment relative to the base at any joint angles (degrees, ``(..., J)``)."""
        raise NotImplementedError

    def key(self) -> tuple:
        """Every number the geometry depends on: robots with equal keys are identical."""
        return tuple(sorted(self.to_json().items(), key=lambda kv: kv[0]))

    # --- JSON ---------------------------------------------------------------------
    def to_json(self) -> dict:
        raise NotImplementedError

    def position_to_json(self, q: Any) -> Any:
        q = [int(v) for v in np.asarray(q).ravel()]
        return q[0] if self.kind == "rotary" else q

    def position_from_json(self, value: Any, field: str, where: str | None) -> tuple[int, ...]:
        """Parse one JSON position (an int for rotary, ``[i, j]`` otherwise); range-checked."""
        if self.kind == "rotary":
            if not _is_int(value):
                raise FormatError(f"{field} must be an integer position, got {_short(value)}", value=value, where=where)
            q = (int(value),)
        else:
            if not isinstance(value, list) or len(value) != self.n_joints or not all(_is_int(v) for v in value):
                raise FormatError(
                    f"{field} must be a list of {self.n_joints} integers {[j.name for j in self.joints]}, got {_short(value)}",
                    value=value, where=where)
            q = tuple(int(v) for v in value)
        for jt, v in zip(self.joints, q):
            if not 0 <= v < jt.steps:
                raise InputError(f"{field}: {jt.name} position {v} is out of range [0, {jt.steps - 1}]", value=value, where=where)
        return q


def _is_int(v: Any) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)
