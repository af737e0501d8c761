"""Joint angles and timed trajectories of a plan (PLAN.json ``angles_deg``, ``trajectories``).

``angles_deg``: the joint angles (degrees) of each configuration, robot by robot
(:meth:`Problem.angles_deg`: each robot's own lattice), a wrapping joint (rotary ``θ``, an
alpha joint without hard stops) reported in ``[0, 360)``.

**Timing model** (``trajectories``, for a joint speed ``v`` in degrees per second;
:mod:`.timing` says it in full and why it is safe):

- a robot's time for step ``k`` (``c_k → c_{k+1}``) is ``τ_{k,p} = max_j |Δθ_{k,p,j}| / v``
  (``Δθ`` the angle the joint turns, the short way round where it wraps, exactly the step
  the planner and the validator check), every joint turning at constant angular velocity;
- a move waits for a neighbour's move of an earlier step only when their swept sets can
  come closer than the buffers allow (certified, :mod:`supcoord.geometry.sweeps_apart`),
  and shares one interval with a neighbour's move of its own step (as long as the slower
  needs: the simultaneous motion the planner certified) only then; otherwise every robot
  goes on at its own pace; ``motion_time_s`` = the last end.  Executing the configurations
  in lockstep, each step lasting its slowest joint, takes ``Σ_k max_p τ_{k,p}``; this timing
  is never slower (kaiju's LCO instance seed 0 at 12°/s on the 13 × 7 lattice: 39.8 s,
  where neighbours moving in one step over one common interval took 49.9 s;
  ``benchmarks/results/vs_kaiju_lco.md`` and its previous version);
- each joint's trajectory is the list of its breakpoints ``[t_s, deg]``: the start (``t = 0``),
  the end (``t = motion_time_s``), and every time its velocity changes (a breakpoint
  between two pieces of equal velocity, to 1e-12 of ``v``, is dropped); between breakpoints
  the joint turns linearly in time.  Angles are continuous (a wrapping joint is not reduced
  modulo 360 along the way, so that the interpolation between two breakpoints is the
  motion); the start is in ``[0, 360)`` where the joint wraps.

``trajectories`` is one object per robot: ``{"alpha": [[t, deg], …], "beta": […]}``
(rotary: ``{"theta": […]}``).  :func:`trajectories_csv` writes the same numbers as
``robot,joint,t_s,deg`` rows.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..geometry.layout import _finite_number, _short
from .problem import Problem
from .timing import plan_timing

__all__ = ["SPEED_RANGE", "check_speed", "wrapped_angles", "continuous_angles", "plan_trajectories",
           "with_motion", "trajectories_csv", "joint_names", "parse_motion_fields", "motion_to_json"]

#: accepted joint speeds (degrees per second)
SPEED_RANGE = (1e-3, 1e5)
#: relative velocity change (of the speed) below which a breakpoint is dropped
_SAME_VELOCITY = 1e-12
#: largest |angle| (degrees) and |time| (seconds) read from a plan
_MAX_DEG, _MAX_T = 1e9, 1e15


def check_speed(speed: Any, where: str = "speed") -> float | None:
    """``speed`` as a float inside :data:`SPEED_RANGE` (None stays None); else a one-line error."""
    if speed is None:
        return None
    lo, hi = SPEED_RANGE
    if not _finite_number(speed) or not lo <= speed <= hi:
        raise InputError(f"must be a joint speed in degrees per second in [{lo:g}, {hi:g}], got {speed!r}",
                         value=speed, where=where)
    return float(speed)


def joint_names(problem: Problem) -> list[str]:
    return [j.name for j in problem.kinematics.joints]


def _wraps(problem: Problem) -> np.ndarray:
    """``(N, J)``: does joint ``j`` of robot ``p`` wrap?"""
    return np.array([[j.wraps for j in problem.kin(p).joints] for p in range(problem.n)], dtype=bool).reshape(
        problem.n, problem.kinematics.n_joints)


def _mod360(a: np.ndarray) -> np.ndarray:
    out = np.mod(a, 360.0)
    return np.where(out >= 360.0, 0.0, out)


def wrapped_angles(problem: Problem, configurations: Any) -> list[np.ndarray]:
    """``angles_deg`` of the configurations: ``(N, J)`` each, wrapping joints in ``[0, 360)``."""
    if not len(configurations):
        return []
    raw = problem.angles_deg(np.asarray(configurations, dtype=float))
    return list(np.where(_wraps(problem), _mod360(raw), raw))


def continuous_angles(problem: Problem, configurations: Any) -> np.ndarray:
    """``(T+1, N, J)`` angles of the configurations without jumps of 360: each step turns a
    wrapping joint the short way round (one lattice step), the start is in ``[0, 360)``."""
    confs = np.asarray(configurations, dtype=np.int64)
    wrapped = np.asarray(wrapped_angles(problem, confs))
    wraps = _wraps(problem)
    kin = problem.kinematics
    out = wrapped.copy()
    for k in range(len(confs) - 1):
        sd = kin.signed_delta(confs[k], confs[k + 1])
        turn = problem.angles_deg(confs[k] + sd) - problem.angles_deg(confs[k])
        guess = out[k] + turn
        out[k + 1] = np.where(wraps, wrapped[k + 1] + 360.0 * np.round((guess - wrapped[k + 1]) / 360.0),
                              wrapped[k + 1])
    return out


def plan_trajectories(problem: Problem, configurations: Any, speed: float,
                      stats: dict | None = None) -> tuple[list[dict], float]:
    """``(trajectories, motion_time_s)`` of the configurations at joint speed ``speed`` (the
    timing of :mod:`.timing`: each move as early as the moves it depends on allow); each
    trajectory maps a joint name to a ``(K, 2)`` array of ``[t_s, deg]``.  ``stats`` (a dict)
    receives the timing's counts (:class:`.timing.Timing`)."""
    speed = check_speed(speed)
    angles = continuous_angles(problem, configurations)
    names = joint_names(problem)
    timing = plan_timing(problem, configurations, speed, angles)
    if stats is not None:
        stats.update(timing.stats)
    total = timing.motion_time_s
    moves: list[list[tuple[float, float, int]]] = [[] for _ in range(problem.n)]  # (start, end, step)
    for k, p, start, end in zip(timing.step.tolist(), timing.robot.tolist(), timing.start.tolist(),
                                timing.end.tolist()):
        moves[p].append((start, end, k))
    out = []
    for p in range(problem.n):
        robot = {}
        for j, name in enumerate(names):
            points = [(0.0, float(angles[0, p, j]))]
            for start, end, k in moves[p]:
                if start > points[-1][0]:
                    points.append((start, float(angles[k, p, j])))
                points.append((end, float(angles[k + 1, p, j])))
            if total > points[-1][0]:
                points.append((total, points[-1][1]))
            robot[name] = _without_straight_points(np.array(points), speed)
        out.append(robot)
    return out, total


def _without_straight_points(points: np.ndarray, speed: float) -> np.ndarray:
    """Drop the breakpoints between two pieces of the same velocity (to 1e-12 of ``speed``)."""
    if len(points) <= 2:
        return points
    velocity = np.diff(points[:, 1]) / np.diff(points[:, 0])
    keep = np.concatenate([[True], np.abs(np.diff(velocity)) > _SAME_VELOCITY * speed, [True]])
    return points[keep]


def with_motion(plan: Any, problem: Problem, speed: float | None = None) -> Any:
    """``plan`` (a complete :class:`~supcoord.problems.plan.Plan`) with ``angles_deg`` and, given a
    ``speed``, ``trajectories`` and ``motion_time_s`` filled in (in place; returned)."""
    speed = check_speed(speed)
    if plan.status != "complete" or not plan.configurations:
        return plan
    plan.angles_deg = wrapped_angles(problem, plan.configurations)
    if speed is not None:
        plan.trajectories, plan.motion_time_s = plan_trajectories(problem, plan.configurations, speed,
                                                                  plan.stats.setdefault("timing", {}))
    return plan


def trajectories_csv(trajectories: list[dict]) -> str:
    """``robot,joint,t_s,deg`` rows (a header first), the numbers as in the JSON (shortest repr)."""
    lines = ["robot,joint,t_s,deg"]
    for p, robot in enumerate(trajectories):
        for name, points in robot.items():
            lines += [f"{p},{name},{float(t)!r},{float(a)!r}" for t, a in np.asarray(points, float)]
    return "\n".join(lines) + "\n"


def motion_to_json(plan: Any) -> dict:
    """The plan's ``trajectories`` and ``motion_time_s`` as JSON (empty when it has none)."""
    if plan.trajectories is None:
        return {}
    trajs = [{name: np.asarray(points, float).tolist() for name, points in robot.items()}
             for robot in plan.trajectories]
    return {"trajectories": trajs, "motion_time_s": plan.motion_time_s}


# --- reading ---------------------------------------------------------------------------------

def _angle(v: Any) -> bool:
    return _finite_number(v) and abs(v) <= _MAX_DEG


def parse_motion_fields(data: dict, problem: Problem, n_confs: int, limit: int,
                        where: str | None) -> tuple[list[np.ndarray], list[dict] | None, float | None]:
    """``angles_deg``, ``trajectories`` and ``motion_time_s`` of a PLAN.json object, checked for
    structure (types, shapes, finite numbers, increasing times; at most ``limit`` numbers in
    all); ranges and geometry are the validator's."""
    n, names = problem.n, joint_names(problem)
    nj = len(names)
    angles: list[np.ndarray] = []
    raw = data.get("angles_deg")
    if raw is not None:
        if not isinstance(raw, list):
            raise FormatError(f"angles_deg must be a list of configurations, got {_short(raw)}", value=raw, where=where)
        if n_confs and len(raw) != n_confs:
            raise FormatError(f"angles_deg has {len(raw)} configurations but configurations has {n_confs}",
                              value=len(raw), where=where)
        if len(raw) * n > limit:
            raise InputError(f"angles_deg: {len(raw)} configurations of {n} positioners are more than the {limit} "
                             f"positions a plan may have", value=len(raw), where=where)
        for t, c in enumerate(raw):
            if not isinstance(c, list) or len(c) != n:
                got = f"{len(c)} positioners" if isinstance(c, list) else _short(c)
                raise FormatError(f"angles_deg[{t}] must list {n} positioners' angles, got {got}", value=c, where=where)
            for i, v in enumerate(c):
                if not isinstance(v, list) or len(v) != nj or not all(_angle(x) for x in v):
                    raise FormatError(f"angles_deg[{t}][{i}] must be {nj} finite angles {names} in degrees "
                                      f"(|a| <= {_MAX_DEG:g}), got {_short(v)}", value=v, where=where)
            angles.append(np.array(c, dtype=float).reshape(n, nj))
    trajs = _parse_trajectories(data.get("trajectories"), n, names, limit, where)
    motion = data.get("motion_time_s")
    if motion is not None and not (_finite_number(motion) and 0 <= motion <= _MAX_T):
        raise FormatError(f"motion_time_s must be a number of seconds >= 0 or null, got {_short(motion)}",
                          value=motion, where=where)
    return angles, trajs, None if motion is None else float(motion)


def _parse_trajectories(raw: Any, n: int, names: list[str], limit: int, where: str | None) -> list[dict] | None:
    if raw is None:
        return None
    if not isinstance(raw, list) or len(raw) != n:
        got = f"{len(raw)} entries" if isinstance(raw, list) else _short(raw)
        raise FormatError(f"trajectories must list {n} positioners' trajectories, got {got}", value=raw, where=where)
    total = 0
    out = []
    for p, robot in enumerate(raw):
        if not isinstance(robot, dict) or set(robot) != set(names):
            got = sorted(robot) if isinstance(robot, dict) else _short(robot)
            raise FormatError(f"trajectories[{p}] must be an object with the joints {names}, got {got}",
                              value=robot, where=where)
        joints = {}
        for name in names:
            points, field = robot[name], f"trajectories[{p}].{name}"
            if not isinstance(points, list) or not points:
                raise FormatError(f"{field} must be a non-empty list of [t_s, deg], got {_short(points)}",
                                  value=points, where=where)
            total += len(points)
            if total > limit:
                raise InputError(f"trajectories: more than the {limit} breakpoints a plan may have", value=total,
                                 where=where)
            for k, pt in enumerate(points):
                if (not isinstance(pt, list) or len(pt) != 2 or not _finite_number(pt[0])
                        or not 0 <= pt[0] <= _MAX_T or not _angle(pt[1])):
                    raise FormatError(f"{field}[{k}] must be [t_s, deg] with 0 <= t_s <= {_MAX_T:g} and a finite "
                                      f"angle, got {_short(pt)}", value=pt, where=where)
                if k and not pt[0] > points[k - 1][0]:
                    raise FormatError(f"{field}[{k}]: times must increase, got {pt[0]!r} after {points[k - 1][0]!r}",
                                      value=pt, where=where)
            joints[name] = np.array(points, dtype=float).reshape(-1, 2)
        out.append(joints)
    return out

