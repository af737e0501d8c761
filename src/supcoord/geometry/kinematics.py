"""Discretised positioner kinematics: joint positions → the colliding segment.

Positions and single moves are those of :mod:`.joint_space` (re-exported here); a move
is one of the supervisor's single events.

Geometry (``docs/formats.md``), angles from +x, counter-clockwise positive:

- ``rotary`` (the seed paper's 1-DOF positioner): ``θ(k) = −2πk/steps``; the arm, the
  colliding segment, goes from the base to ``arm·(cos θ, sin θ)``; index ``k + 1`` is
  one step clockwise (the paper's forward event ``v``); ``steps − 1`` and ``0`` are
  neighbours.
- ``alpha-beta`` (SDSS-V-like, 2 DOF; :mod:`.alpha_beta`): ``α(i) = 2πi/A`` (wrapping, or
  with hard stops over ``alpha_range``), ``β(j) = lo + (hi − lo)·j/(B − 1)`` with hard stops
  at ``j = 0`` and ``j = B − 1``, or each robot's own lattice holding its exact start and
  target angles (:mod:`.lattice`); the elbow at ``alpha·(cos α, sin α)``; the beta arm, the
  colliding segment, from the elbow to the fibre ``elbow + beta·(cos(α+β), sin(α+β))``.

Motion between positions is linear in joint space (in angle between a lattice's positions): :meth:`Kinematics.segments`
accepts fractional joint positions, so ``q + t·δ`` for ``t ∈ [0, 1]`` is the pose at
time ``t`` of a step, and :meth:`Kinematics.sweep_length` bounds how far any point of
the colliding segment travels along it (what makes sampled swept checks sound).

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, Supervisory coordination of robotic fiber
  positioners in multi-object spectrographs, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (rotary model).
- C. Sayres et al., kaiju: collision-avoidance path planning for SDSS-V robots (alpha-beta).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from .alpha_beta import AlphaBeta
from .chain import chain_angles_deg, chain_segments
from .joint_space import MAX_LENGTH, MAX_POSITIONS, Joint, Kinematics, _is_int
from .lattice import exact_lattice
from .layout import _positive_number, _short

__all__ = ["Joint", "Kinematics", "Rotary", "AlphaBeta", "exact_lattice", "kinematics_from_spec", "MAX_LENGTH",
           "MAX_POSITIONS"]


class Rotary(Kinematics):
    """The seed paper's one-joint positioner: ``θ(k) = −2πk/steps``, the arm from base to fibre.

    >>> kin = Rotary(15.0, 12)
    >>> kin.segments([3]).round(6).tolist()   # k = 3: a quarter turn clockwise, pointing −y
    [[0.0, 0.0], [0.0, -15.0]]
    """

    kind = "rotary"

    def __init__(self, arm: float, steps: int):
        if not _positive_number(arm) or arm > MAX_LENGTH:
            raise InputError(f"kinematics.arm must be a positive number (mm) <= {MAX_LENGTH:g}, got {arm!r}", value=arm)
        if not _is_int(steps) or steps < 2:
            raise InputError(f"kinematics.steps must be an integer >= 2, got {steps!r}", value=steps)
        if steps > MAX_POSITIONS:
            raise InputError(f"kinematics.steps must be at most {MAX_POSITIONS} (a pair's collision tables hold "
                             f"steps² entries), got {steps}", value=steps)
        self.arm = float(arm)
        self.steps = int(steps)
        self.joints = (Joint("theta", self.steps, True),)

    def __repr__(self) -> str:
        return f"Rotary(arm={self.arm}, steps={self.steps})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Rotary) and (self.arm, self.steps) == (other.arm, other.steps)

    __hash__ = None  # type: ignore[assignment]

    @property
    def reach(self) -> float:
        return self.arm

    def theta(self, q: Any) -> np.ndarray:
        """``θ = −2πk/steps`` in radians for (fractional) positions ``q`` ``(..., 1)``."""
        q = np.asarray(q, dtype=float)
        return -2 * np.pi * q[..., 0] / self.steps

    def segments(self, q: Any) -> np.ndarray:
        return self._segments_at(self.theta(q))

    def joint_angles_deg(self, q: Any) -> np.ndarray:
        """``θ`` in degrees (``(..., 1)``) for (fractional) positions ``q``: ``−360·k/steps``."""
        q = np.asarray(q, dtype=float)
        return -360.0 * q / self.steps

    def segments_at_deg(self, angles_deg: Any) -> np.ndarray:
        """The arm (relative to the base) at angles ``θ`` in degrees ``(..., 1)``."""
        return self._segments_at(chain_angles_deg(angles_deg, self.chain_offsets_deg())[1])

    def chain_offsets_deg(self) -> tuple[float, ...]:
        return (0.0,)

    def _segments_at(self, theta: np.ndarray) -> np.ndarray:
        l1, seg = self.chain()
        return chain_segments(l1, seg, 0.0, theta)

    def chain(self) -> tuple[float, tuple[tuple[float, float], tuple[float, float]]]:
        """No first link: the arm is the second link, from the base to ``(arm, 0)`` turned by ``θ``."""
        return 0.0, ((0.0, 0.0), (self.arm, 0.0))

    def chain_angles(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        theta = self.theta(q)
        return np.zeros_like(theta), theta

    def sweep_length(self, delta: Any) -> np.ndarray:
        delta = np.asarray(delta, dtype=float)
        return self.arm * np.abs(delta[..., 0]) * 2 * np.pi / self.steps

    def rotation(self, q: Any, joint: int, delta: Any) -> tuple[np.ndarray, np.ndarray]:
        q = np.asarray(q, dtype=float)
        angle = -2 * np.pi * np.broadcast_to(np.asarray(delta, float), q.shape[:-1]) / self.steps
        return np.zeros(q.shape[:-1] + (2,)), angle

    def to_json(self) -> dict:
        return {"kind": "rotary", "arm": self.arm, "steps": self.steps}


def kinematics_from_spec(spec: Any, where: str | None = None) -> Kinematics:
    """Parse a PROBLEM.json ``kinematics`` object; errors name the field and value."""
    if not isinstance(spec, dict):
        raise FormatError(f"kinematics must be an object, got {_short(spec)}", value=spec, where=where)
    kind = spec.get("kind")
    try:
        if kind == "rotary":
            _require(spec, ("arm", "steps"), where)
            _wrapping_steps(spec, "steps")
            return Rotary(spec["arm"], spec["steps"])
        if kind == "alpha-beta":
            _require(spec, ("alpha", "beta", "alpha_steps", "beta_steps"), where)
            if "alpha_range" not in spec:
                _wrapping_steps(spec, "alpha_steps")
            return AlphaBeta(spec["alpha"], spec["beta"], spec["alpha_steps"], spec["beta_steps"],
                             spec.get("beta_range", [0.0, 180.0]), alpha_range=spec.get("alpha_range"))
    except InputError as exc:
        if exc.where is None:
            exc.where = where
            exc.args = (exc.one_line(),)
        raise
    raise FormatError(f"kinematics.kind must be 'rotary' or 'alpha-beta', got {_short(kind)}", value=kind, where=where)


def _wrapping_steps(spec: dict, field: str) -> None:
    """A wrapping joint of a problem needs at least 3 steps: with 2, both moves reach the same
    position by opposite half-turns, so a plan's configurations cannot say which turn was
    made (and the way back would not retrace the way there)."""
    v = spec[field]
    if _is_int(v) and v == 2:
        raise InputError(f"kinematics.{field} must be at least 3 for a joint that wraps (with 2 steps both moves "
                         f"reach the same position by opposite half-turns), got 2", value=v)


def _require(spec: dict, fields: tuple[str, ...], where: str | None) -> None:
    for f in fields:
        if f not in spec:
            raise FormatError(f"kinematics.{f} is missing (kind {spec.get('kind')!r})", value=None, where=where)
