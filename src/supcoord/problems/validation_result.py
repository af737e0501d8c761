"""The verdict of the independent validator (:func:`supcoord.problems.validate.validate_plan`)
as a typed result, and its JSON (what ``supcoord check --json`` prints)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["ValidationResult", "Incident"]


@dataclass(frozen=True)
class Incident:
    """One collision the validator lists (:attr:`ValidationResult.incidents`).

    Attributes
    ----------
    step : int
        The step ``k`` (from configuration ``k`` to ``k + 1``) where it happens.
    positioners : list of int
        The colliding pair ``[a, b]``, or ``[a]`` against an obstacle.
    t : float
        When in the step the distance is least, in [0, 1].
    distance : float
        The least distance seen (mm).
    required : float
        The distance the pair needs, ``r_a + r_b`` (mm).
    obstacle : int or None
        The obstacle hit (its index), None for a pair of positioners.
    """

    step: int
    positioners: list[int]
    t: float
    distance: float
    required: float
    obstacle: int | None = None

    def to_json(self) -> dict[str, Any]:
        """The incident as ``supcoord check --json`` prints it (``obstacle`` only against one)."""
        out: dict[str, Any] = {"step": self.step, "positioners": list(self.positioners), "t": self.t,
                               "distance": self.distance, "required": self.required}
        if self.obstacle is not None:
            out["obstacle"] = self.obstacle
        return out


@dataclass(frozen=True)
class ValidationResult:
    """The verdict of :func:`validate_plan` on one plan (its module docstring's rule).

    Attributes
    ----------
    valid : bool
        No problem found: start to target, joints in range, no collision.
    collisions : int
        Colliding (step, pair) incidents, and (step, robot, obstacle) ones.
    at_target : int
        Robots whose last position is their target.
    problems : list of str
        One line per problem found, at most :data:`~.validate.MAX_PROBLEMS` (then ``"... and N more"``).
    steps : int
        Steps of the motion checked.
    min_clearance : float or None
        The least ``dist − (r_a + r_b)`` seen (mm); None when nothing was measured.
    incidents : list of Incident
        The first collisions (step, positioners, ``t`` in [0, 1] of the step, distances in mm;
        against an obstacle also which one).
    undecided : int
        Pairs accepted touching along a stretch, which no sampling settles.
    undecided_depth : float
        How deep a collision those pairs could hide at most (mm).
    motion_time_s : float or None
        The last breakpoint time (s) of a plan with trajectories, else None.
    """

    valid: bool
    collisions: int
    at_target: int
    problems: list[str]
    steps: int
    min_clearance: float | None
    incidents: list[Incident]
    undecided: int = 0
    undecided_depth: float = 0.0
    motion_time_s: float | None = None

    def to_json(self) -> dict[str, Any]:
        """The verdict as ``supcoord check --json`` prints it (``motion_time_s`` only when the
        plan has trajectories)."""
        out = {"valid": self.valid, "collisions": self.collisions, "at_target": self.at_target,
               "problems": list(self.problems), "steps": self.steps, "min_clearance": self.min_clearance,
               "incidents": [i.to_json() for i in self.incidents], "undecided": self.undecided, "undecided_depth": self.undecided_depth}
        if self.motion_time_s is not None:
            out["motion_time_s"] = self.motion_time_s
        return out
