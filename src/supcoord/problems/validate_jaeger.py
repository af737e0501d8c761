"""The validator's check of a trajectory in jaeger's format, exactly as written (``supcoord check --jaeger``).

A jaeger file (SDSS-V's robot controller; written by :func:`supcoord.problems.jaeger.jaeger_paths`,
by kaiju's ``getPathPair`` or by anyone) is a JSON object ``{positioner_id: {"alpha": [[deg,
s], …], "beta": [[deg, s], …]}}``, or jaeger's own trajectory dump ``{"trajectory": {…}, …}``.
Its motion is what the robots run: each joint linear in time between its points, holding its
first angle before the first point and its last after the last; a robot the file does not
list stands at its start.  That motion, every robot at once, is checked by the validator
(:func:`.validate.validate_plan` on the trajectories alone: robots, fixed obstacles, the joint
rules, the joint ranges, the start and the target, sampled and bisected to 1e-6 mm), with the
problem's collision definition (an instrument's own by default: SDSS-V's is kaiju's).
Besides, every piece's joint speed is compared with the limit (``max_rpm``, default the
instrument's largest, SDSS-V 3 RPM).  Nothing of the planner or of the export is used.

The result names the first collision in time: the two robots (indices and positioner IDs),
the time (s, in the file's clock) and the clearance there (distance minus the required one).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..geometry.layout import _finite_number, _short
from ..instruments import load_instrument, motion_limits
from .plan import Plan, exchanged
from .problem import Problem, read_json
from .validate import trajectory_poses, validate_plan

__all__ = ["JaegerCheck", "read_jaeger", "check_jaeger", "MAX_JAEGER_BYTES"]

#: largest jaeger file read (bytes)
MAX_JAEGER_BYTES = 256 * 2**20
_JOINTS = ("alpha", "beta")


@dataclass
class JaegerCheck:
    """The verdict on a jaeger trajectory (module docstring).

    ``valid``; ``collisions`` (pair incidents, as the validator counts them); ``first``: the
    earliest collision, ``{"robots": [a, b], "positioner_ids": [..], "obstacle": o (a robot
    against a fixed obstacle), "time_s", "distance_mm", "required_mm", "clearance_mm"}`` or
    None; ``min_clearance_mm`` over the whole motion; ``max_speed_deg_s`` of any piece and the
    ``speed_limit_deg_s``; ``motion_time_s`` (the last point); ``points``; ``problems`` (the
    validator's, and a speed over the limit)."""

    valid: bool
    collisions: int
    first: dict | None
    min_clearance_mm: float | None
    max_speed_deg_s: float
    speed_limit_deg_s: float
    motion_time_s: float
    points: int
    problems: list[str] = field(default_factory=list)
    undecided: int = 0

    def to_json(self) -> dict:
        return {"valid": self.valid, "collisions": self.collisions, "first_collision": self.first,
                "min_clearance_mm": self.min_clearance_mm, "max_speed_deg_s": self.max_speed_deg_s,
                "speed_limit_deg_s": self.speed_limit_deg_s, "motion_time_s": self.motion_time_s,
                "points": self.points, "undecided": self.undecided, "problems": list(self.problems)}


def _keys(problem: Problem) -> list[str]:
    if problem.layout.get("kind") == "instrument":
        return [str(int(i)) for i in load_instrument(problem.layout["name"]).positioner_ids]
    return [str(p) for p in range(problem.n)]


def read_jaeger(data: Any, problem: Problem, where: str | None = None) -> list[dict[str, np.ndarray]]:
    """Per robot ``{"alpha": (K, 2) [t, deg], "beta": …}`` (the validator's trajectories) from a
    jaeger object; a robot not listed holds its start.  Errors name the key, joint and index."""
    if isinstance(data, dict) and isinstance(data.get("trajectory"), dict):
        data = data["trajectory"]  # jaeger's dump of a sent trajectory
    if not isinstance(data, dict) or not data:
        raise FormatError(f"a jaeger trajectory must be a non-empty object of positioner IDs, got {_short(data)}",
                          value=data, where=where)
    index = {k: p for p, k in enumerate(_keys(problem))}
    start = problem.angles_deg(problem.start)
    out: list[dict[str, np.ndarray] | None] = [None] * problem.n
    for key, robot in data.items():
        name = str(key).strip()
        if name not in index:
            raise FormatError(f"{_short(key)} is not a positioner ID of this problem", value=key, where=where)
        if not isinstance(robot, dict) or set(robot) != set(_JOINTS):
            raise FormatError(f"{name} must be {{\"alpha\": [[deg, s], ...], \"beta\": [[deg, s], ...]}}, got "
                              f"{_short(robot)}", value=robot, where=where)
        out[index[name]] = {joint: _joint_points(f"{name}.{joint}", robot[joint], where) for joint in _JOINTS}
    return [r if r is not None else {j: np.array([[0.0, float(start[p, i])]]) for i, j in enumerate(_JOINTS)}
            for p, r in enumerate(out)]


def _joint_points(name: str, pts: Any, where: str | None) -> np.ndarray:
    """One joint's jaeger points ``[[deg, s], ...]`` as the validator's ``(K, 2) [t, deg]``;
    ``name``: ``"<positioner ID>.<joint>"``, named by every error."""
    if not isinstance(pts, list) or not pts:
        raise FormatError(f"{name} must be a non-empty list of [deg, s]", value=pts, where=where)
    for i, pt in enumerate(pts):
        if not (isinstance(pt, (list, tuple)) and len(pt) == 2 and all(_finite_number(v) for v in pt)
                and abs(pt[0]) <= 1e9 and 0 <= pt[1] <= 1e15):
            raise FormatError(f"{name}[{i}] must be [deg, s] (|deg| <= 1e9, 0 <= s <= 1e15), got "
                              f"{_short(pt)}", value=pt, where=where)
        if i and pt[1] <= pts[i - 1][1]:
            raise FormatError(f"{name}[{i}]: times must increase, got {pt[1]!r} after "
                              f"{pts[i - 1][1]!r}", value=pt[1], where=where)
    return np.array([[float(t), float(a)] for a, t in pts])


def check_jaeger(problem: Problem, source: Any, *, max_rpm: float | None = None, reverse: bool = False,
                 resolution: float = 0.05) -> JaegerCheck:
    """Check a jaeger trajectory against ``problem`` (module docstring).

    Parameters
    ----------
    problem : an alpha-beta problem (an instrument layout: keys are its positioner IDs).
    source : a path to a jaeger JSON file, or the decoded object.
    max_rpm : the speed limit (RPM; default the instrument's largest, else 3).
    reverse : the file runs back, from the problem's targets to its starts (kaiju's
        ``fromDestination``, ``solve --jaeger-reverse``).
    resolution : the validator's first sampling (mm); the verdict does not depend on it.
    """
    if problem.kinematics.kind != "alpha-beta":
        raise InputError(f"a jaeger trajectory moves alpha-beta robots, the problem's are {problem.kinematics.kind}",
                         value=problem.kinematics.kind, where=problem.where)
    if reverse:
        problem = exchanged(problem)
    where = None
    if isinstance(source, (str, Path)):
        where = str(source)
        source = read_json(source, "jaeger trajectory", MAX_JAEGER_BYTES)
    trajs = read_jaeger(source, problem, where)
    inst = problem.layout.get("name") if problem.layout.get("kind") == "instrument" else None
    if max_rpm is None:
        max_rpm = motion_limits(inst).max_rpm if inst else 3.0
    if not _finite_number(max_rpm) or max_rpm <= 0:
        raise InputError(f"must be a speed in RPM > 0, got {max_rpm!r}", value=max_rpm, where="max_rpm")
    limit = float(max_rpm) * 6.0
    result = validate_plan(problem, Plan("complete", trajectories=trajs), resolution)
    times, _ = trajectory_poses(trajs)
    problems = list(result.problems)
    fastest = max((float(np.max(np.abs(np.diff(a[:, 1]) / np.diff(a[:, 0])))) for r in trajs for a in r.values()
                   if len(a) > 1), default=0.0)
    if fastest > limit * (1 + 1e-9):
        problems.append(f"a joint turns at {fastest:.6g} deg/s, faster than the limit {limit:g} deg/s "
                        f"({max_rpm:g} RPM)")
    keys = _keys(problem)
    first = None
    for inc in result.incidents:
        k = inc.step
        t = float(times[k] + inc.t * (times[k + 1] - times[k])) if k + 1 < len(times) else float(times[k])
        if first is None or t < first["time_s"]:
            robots = [int(r) for r in inc.positioners]
            first = {"robots": robots, "positioner_ids": [keys[r] for r in robots], "time_s": t,
                     "distance_mm": inc.distance, "required_mm": inc.required,
                     "clearance_mm": inc.distance - inc.required}
            if inc.obstacle is not None:
                first["obstacle"] = int(inc.obstacle)
    points = sum(len(a) for r in source.get("trajectory", source).values() for a in r.values())
    return JaegerCheck(not problems, int(result.collisions), first, result.min_clearance, fastest, limit,
                       float(times[-1]), points, problems, int(result.undecided))
