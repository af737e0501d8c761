"""The verdict of the independent validator (:func:`supcoord.problems.validate.validate_plan`)
as a typed result, and its JSON (what ``supcoord check --json`` prints)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["ValidationResult"]


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
    incidents : list of dict
        The first collisions: ``{"step", "positioners", "t", "distance", "required"}`` (``t`` in
        [0, 1] of the step, distances in mm; against an obstacle also ``"obstacle"``).
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
    incidents: list[dict[str, Any]]
    undecided: int = 0
    undecided_depth: float = 0.0
    motion_time_s: float | None = None

    def to_json(self) -> dict[str, Any]:
        """The verdict as ``supcoord check --json`` prints it (``motion_time_s`` only when the
        plan has trajectories)."""
        out = {"valid": self.valid, "collisions": self.collisions, "at_target": self.at_target,
               "problems": list(self.problems), "steps": self.steps, "min_clearance": self.min_clearance,
               "incidents": list(self.incidents), "undecided": self.undecided, "undecided_depth": self.undecided_depth}
        if self.motion_time_s is not None:
            out["motion_time_s"] = self.motion_time_s
        return out

    def __getitem__(self, key: str) -> Any:
        """The JSON field ``key`` of :meth:`to_json`: ``result["valid"]``, the call form of the
        dictionary :func:`validate_plan` returned before this class."""
        return self.to_json()[key]
