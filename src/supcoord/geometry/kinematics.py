"""Discretised positioner kinematics: joint positions → the colliding segment.

Positions and single moves are those of :mod:`.joint_space` (re-exported here); a move
is one of the supervisor's single events.

Geometry (``docs/formats.md``), angles from +x, counter-clockwise positive:

- ``rotary`` (the seed paper's 1-DOF positioner): ``θ(k) = −2πk/steps``; the arm, the
  colliding segment, goes from the base to ``arm·(cos θ, sin θ)``; index ``k + 1`` is
  one step clockwise (the paper's forward event ``v``); ``steps − 1`` and ``0`` are
  neighbours.
- ``alpha-beta`` (SDSS-V-like, 2 DOF): ``α(i) = 2πi/A`` (wrapping),
  ``β(j) = lo + (hi − lo)·j/(B − 1)`` with hard stops at ``j = 0`` and ``j = B − 1``; the
  elbow at ``alpha·(cos α, sin α)``; the beta arm, the colliding segment, from the
  elbow to the fibre ``elbow + beta·(cos(α+β), sin(α+β))``.

Motion between positions is linear in joint space: :meth:`Kinematics.segments`
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

import math
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from .joint_space import Joint, Kinematics, _is_int
from .layout import _finite_number, _positive_number, _short

__all__ = ["Joint", "Kinematics", "Rotary", "AlphaBeta", "kinematics_from_spec", "MAX_LENGTH", "MAX_POSITIONS"]

#: longest arm accepted (mm); anything longer is a unit mistake
MAX_LENGTH = 1e6
#: most positions of one positioner: a pair's collision tables hold positions² entries, and
#: :data:`supcoord.geometry.collision.MAX_TABLE_ENTRIES` is ``MAX_POSITIONS²`` (5·10⁷)
MAX_POSITIONS = 7071


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
        theta = self.theta(q)
        end = self.arm * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
        return np.stack([np.zeros_like(end), end], axis=-2)

    def sweep_length(self, delta: Any) -> np.ndarray:
        delta = np.asarray(delta, dtype=float)
        return self.arm * np.abs(delta[..., 0]) * 2 * np.pi / self.steps

    def rotation(self, q: Any, joint: int, delta: Any) -> tuple[np.ndarray, np.ndarray]:
        q = np.asarray(q, dtype=float)
        angle = -2 * np.pi * np.broadcast_to(np.asarray(delta, float), q.shape[:-1]) / self.steps
        return np.zeros(q.shape[:-1] + (2,)), angle

    def to_json(self) -> dict:
        return {"kind": "rotary", "arm": self.arm, "steps": self.steps}


class AlphaBeta(Kinematics):
    """Two joints (SDSS-V-like): ``α = 2πi/A`` wrapping, ``β = lo + (hi−lo)·j/(B−1)`` with hard stops.

    >>> kin = AlphaBeta(7.4, 15.0, 4, 3, (0.0, 180.0))
    >>> kin.segments([1, 0]).round(6).tolist()   # α = 90°, β = 0: arm straight up +y
    [[0.0, 7.4], [0.0, 22.4]]
    """

    kind = "alpha-beta"

    def __init__(self, alpha: float, beta: float, alpha_steps: int, beta_steps: int,
                 beta_range: tuple[float, float] = (0.0, 180.0)):
        for name, v in (("alpha", alpha), ("beta", beta)):
            if not _positive_number(v) or v > MAX_LENGTH:
                raise InputError(f"kinematics.{name} must be a positive arm length (mm) <= {MAX_LENGTH:g}, got {v!r}", value=v)
        if not _is_int(alpha_steps) or alpha_steps < 2:
            raise InputError(f"kinematics.alpha_steps must be an integer >= 2, got {alpha_steps!r}", value=alpha_steps)
        if not _is_int(beta_steps) or beta_steps < 2:
            raise InputError(f"kinematics.beta_steps must be an integer >= 2, got {beta_steps!r}", value=beta_steps)
        if alpha_steps * beta_steps > MAX_POSITIONS:
            raise InputError(f"kinematics.alpha_steps × beta_steps must be at most {MAX_POSITIONS} positions (a "
                             f"pair's collision tables hold positions² entries), got {alpha_steps} × {beta_steps}",
                             value=[alpha_steps, beta_steps])
        if (not isinstance(beta_range, (list, tuple)) or len(beta_range) != 2
                or not all(_finite_number(v) for v in beta_range)):
            raise InputError(f"kinematics.beta_range must be [lo, hi] in degrees, got {_short(beta_range)}", value=beta_range)
        lo, hi = float(beta_range[0]), float(beta_range[1])
        if not (-360.0 <= lo < hi <= 360.0 and hi - lo <= 360.0):
            raise InputError(f"kinematics.beta_range must satisfy -360 <= lo < hi <= 360 and hi - lo <= 360, got {[lo, hi]}",
                             value=beta_range)
        self.alpha, self.beta = float(alpha), float(beta)
        self.alpha_steps, self.beta_steps = int(alpha_steps), int(beta_steps)
        self.beta_range = (lo, hi)
        self.joints = (Joint("alpha", self.alpha_steps, True), Joint("beta", self.beta_steps, False))

    def __repr__(self) -> str:
        return (f"AlphaBeta(alpha={self.alpha}, beta={self.beta}, alpha_steps={self.alpha_steps}, "
                f"beta_steps={self.beta_steps}, beta_range={list(self.beta_range)})")

    def __eq__(self, other: object) -> bool:
        return isinstance(other, AlphaBeta) and self.to_json() == other.to_json()

    __hash__ = None  # type: ignore[assignment]

    def angles(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(α, β)`` in radians for (fractional) positions ``q``."""
        q = np.asarray(q, dtype=float)
        lo, hi = np.radians(self.beta_range)
        a = 2 * np.pi * q[..., 0] / self.alpha_steps
        b = lo + (hi - lo) * q[..., 1] / (self.beta_steps - 1)
        return a, b

    @property
    def beta_step_rad(self) -> float:
        lo, hi = self.beta_range
        return math.radians(hi - lo) / (self.beta_steps - 1)

    @property
    def reach(self) -> float:
        """``max(alpha, max_β |fibre|)``: the distance from the base is convex along the beta
        arm, so its farthest point is an end — the elbow (at ``alpha``) or the fibre, at
        ``√(a² + b² + 2ab·cos β)``, largest where ``cos β`` is over ``[lo, hi]``."""
        lo, hi = np.radians(self.beta_range)
        # max over β ∈ [lo, hi] of cos β: 1 if a multiple of 2π lies inside, else at an end
        k = math.ceil(lo / (2 * math.pi))
        cmax = 1.0 if 2 * math.pi * k <= hi else max(math.cos(lo), math.cos(hi))
        fibre = math.sqrt(max(0.0, self.alpha**2 + self.beta**2 + 2 * self.alpha * self.beta * cmax))
        return max(self.alpha, fibre)

    def segments(self, q: Any) -> np.ndarray:
        a, b = self.angles(q)
        elbow = self.alpha * np.stack([np.cos(a), np.sin(a)], axis=-1)
        fibre = elbow + self.beta * np.stack([np.cos(a + b), np.sin(a + b)], axis=-1)
        return np.stack([elbow, fibre], axis=-2)

    def sweep_length(self, delta: Any) -> np.ndarray:
        # a point of the beta arm is within `reach` of the base (α turns it about the base)
        # and within `beta` of the elbow (β turns it about the elbow)
        delta = np.asarray(delta, dtype=float)
        da = np.abs(delta[..., 0]) * 2 * np.pi / self.alpha_steps
        db = np.abs(delta[..., 1]) * self.beta_step_rad
        return self.reach * da + self.beta * db

    def rotation(self, q: Any, joint: int, delta: Any) -> tuple[np.ndarray, np.ndarray]:
        # alpha turns the whole arm about the base; beta turns the beta arm about the elbow
        q = np.asarray(q, dtype=float)
        delta = np.broadcast_to(np.asarray(delta, float), q.shape[:-1])
        if joint == 0:
            return np.zeros(q.shape[:-1] + (2,)), 2 * np.pi * delta / self.alpha_steps
        return self.segments(q)[..., 0, :], delta * self.beta_step_rad

    def to_json(self) -> dict:
        return {"kind": "alpha-beta", "alpha": self.alpha, "beta": self.beta, "alpha_steps": self.alpha_steps,
                "beta_steps": self.beta_steps, "beta_range": list(self.beta_range)}


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
            _wrapping_steps(spec, "alpha_steps")
            return AlphaBeta(spec["alpha"], spec["beta"], spec["alpha_steps"], spec["beta_steps"],
                             spec.get("beta_range", [0.0, 180.0]))
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
