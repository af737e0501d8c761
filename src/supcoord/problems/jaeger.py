"""A plan as SDSS-V's robot controller jaeger runs it: trajectories in jaeger's format.

jaeger (``src/jaeger/commands/trajectory.py``: ``send_trajectory``, ``Trajectory``) takes a
trajectory as ``{positioner_id: {"alpha": [(deg, s), …], "beta": [(deg, s), …]}}``: each
joint's points, its own number of them, angle first and time (seconds) second; the robot
moves linearly in time between points and holds the last.  kaiju's ``getPathPair`` writes the
same, one path to the targets and one back.  :func:`jaeger_paths` writes a complete plan so:

- keys: the instrument table's positioner IDs (as strings, as JSON has them; jaeger's
  ``send_trajectory`` takes them as integers); for a problem without an instrument, the
  robot's index; offline robots (``"offline"``) are left out, as kaiju leaves them out;
- timing: the plan's own (:mod:`.timing`: each robot at its own pace, a neighbour waiting only
  where their motions can meet) at the joint speed ``rpm`` (1 RPM = 6°/s; default the
  instrument's, SDSS-V 2 RPM, at most ``max_rpm``), every time shifted by ``start_delay_s``
  (default the instrument's, jaeger's 1 s path delay: the first point of every joint is at
  that time, as in kaiju's paths);
- with an ``acceleration`` limit (deg/s²), each move lasts as long as a trapezoidal profile
  needs (ramps of ``speed/acceleration`` s, or a triangle for short moves), all joints of the
  move and every neighbour's move synchronised with it following the same profile over the
  same interval, so every pose is still one the timing certified; each ramp is written as
  :data:`RAMP_PIECES` linear pieces (the velocity changes by at most ``acceleration·Δt``
  between consecutive pieces, and never exceeds the speed);
- each joint's points are as few as the motion allows: a point between two pieces of the
  same velocity is dropped, and so is a last point that only holds the angle; the first
  point is the start angle and the last the target angle exactly (the problem's own, for the
  reverse path the other way round), times strictly increasing.

A ``partial`` plan is exported the same way: each robot off target follows its own path to
where the plan leaves it (its start, or folded: :func:`.off_target.partial_end`), which is its last point
(the first of the reverse path); PLAN.json's ``off_target`` names those robots, and
``supcoord check PROBLEM PLAN.json --jaeger PATHS.json`` checks the file against the plan's ends.

The reverse path (``reverse=True``) is the same motion run backwards in time, from the
targets to the starts, as kaiju's ``fromDestination``.  The motion between the exported
points, every robot at once, is what ``supcoord check --jaeger`` validates
(:mod:`.validate_jaeger`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..geometry.layout import _finite_number
from ..instruments import load_instrument, motion_limits
from ..outputs import atomic_write_text, check_output
from .off_target import folded_ends, partial_end
from .plan import Plan
from .problem import Problem
from .refine import at_lattice
from .timing import plan_timing
from .trajectory import continuous_angles

__all__ = ["JaegerPaths", "jaeger_paths", "jaeger_limits", "positioner_keys", "write_jaeger", "RAMP_PIECES", "DEFAULT_MAX_RPM"]

#: linear pieces of each acceleration ramp
RAMP_PIECES = 4
#: the speed limit without an instrument (RPM; SDSS-V's robots: at most 3)
DEFAULT_MAX_RPM = 3.0
#: relative velocity change below which a point between two pieces is dropped
_SAME_VELOCITY = 1e-12


@dataclass
class JaegerPaths:
    """One direction of a plan in jaeger's format.

    ``paths``: positioner ID (string) → ``{"alpha": [[deg, s], …], "beta": [[deg, s], …]}``;
    ``motion_time_s``: the last point's time (s, the start delay included);
    ``speed_deg_s``: the joint speed limit used; ``max_speed_deg_s``: the fastest piece
    written; ``acceleration_deg_s2``: the limit (None: none); ``start_delay_s``; ``points``:
    the number of points written."""

    paths: dict[str, dict[str, list[list[float]]]]
    motion_time_s: float
    speed_deg_s: float
    max_speed_deg_s: float
    acceleration_deg_s2: float | None
    start_delay_s: float
    points: int

    def to_json(self) -> dict:
        """The file's JSON object (jaeger's format, nothing else)."""
        return self.paths


def positioner_keys(problem: Problem) -> list[str]:
    """Each robot's key in a jaeger file: the instrument table's positioner ID, else its index."""
    layout = problem.layout
    if layout.get("kind") == "instrument":
        return [str(int(i)) for i in load_instrument(layout["name"]).positioner_ids]
    return [str(p) for p in range(problem.n)]


def jaeger_limits(problem: Problem, rpm: Any = None, acceleration: Any = None,
                  start_delay_s: Any = None) -> tuple[float, float | None, float]:
    """``(speed deg/s, acceleration deg/s² or None, delay s)`` of :func:`jaeger_paths`, the
    instrument's defaults filled in; a value out of range is a one-line :class:`InputError`
    whose ``where`` names the parameter (``rpm``, ``acceleration``, ``start_delay_s``)."""
    inst = problem.layout.get("name") if problem.layout.get("kind") == "instrument" else None
    lim = motion_limits(inst) if inst else None
    max_rpm = lim.max_rpm if lim else DEFAULT_MAX_RPM
    if rpm is None:
        if lim is None:
            raise InputError("needs a joint speed in RPM (the problem has no instrument to take it from)",
                             value=None, where="rpm")
        rpm = lim.rpm
    if not _finite_number(rpm) or not 0 < rpm <= max_rpm:
        raise InputError(f"must be a speed in RPM in (0, {max_rpm:g}], got {rpm!r}", value=rpm, where="rpm")
    if acceleration is not None and (not _finite_number(acceleration) or not 0 < acceleration <= 1e6):
        raise InputError(f"must be an acceleration in deg/s² in (0, 1e6], got {acceleration!r}",
                         value=acceleration, where="acceleration")
    delay = (lim.start_delay_s if lim else 0.0) if start_delay_s is None else start_delay_s
    if not _finite_number(delay) or not 0 <= delay <= 3600:
        raise InputError(f"must be a delay in seconds in [0, 3600], got {delay!r}", value=delay,
                         where="start_delay_s")
    return float(rpm) * 6.0, None if acceleration is None else float(acceleration), float(delay)


def _profile(span: float, speed: float, accel: float | None) -> tuple[np.ndarray, np.ndarray]:
    """A move over ``span`` seconds as fractions ``(τ/span, s)`` of its time and its turn:
    linear, or trapezoidal with ramps of ``min(speed/accel, span/2)`` seconds."""
    if accel is None:
        return np.array([0.0, 1.0]), np.array([0.0, 1.0])
    r = min(speed / accel, span / 2) / span          # ramp, as a fraction of the span
    peak = 1.0 / (1.0 - r)                           # normalised cruise velocity
    up = np.linspace(0.0, r, RAMP_PIECES + 1)
    tau = np.concatenate([up, 1.0 - up[::-1]])
    s = np.where(tau <= r, peak * tau * tau / (2 * r), np.where(tau >= 1 - r, 1 - peak * (1 - tau) ** 2 / (2 * r),
                                                                peak * (tau - r / 2)))
    keep = np.concatenate([[True], np.diff(tau) > 0])  # a triangle's two ramps meet at one point
    return tau[keep], s[keep]


def _move_time(speed: float, accel: float | None):
    """Each move's time from its largest joint turn (degrees): the trapezoid's, or ``turn/speed``."""
    def duration(turn: np.ndarray) -> np.ndarray:
        if accel is None:
            return turn / speed
        return np.where(turn >= speed * speed / accel, turn / speed + speed / accel, 2 * np.sqrt(turn / accel))
    return duration


def _simplified(points: np.ndarray, speed: float) -> np.ndarray:
    """Drop points between two pieces of the same velocity, then a last point that only holds."""
    if len(points) > 2:
        velocity = np.diff(points[:, 1]) / np.diff(points[:, 0])
        keep = np.concatenate([[True], np.abs(np.diff(velocity)) > _SAME_VELOCITY * speed, [True]])
        points = points[keep]
    if len(points) > 2 and points[-1, 1] == points[-2, 1]:
        points = points[:-1]
    return points


def jaeger_paths(problem: Problem, plan: Plan, *, rpm: float | None = None, acceleration: float | None = None,
                 start_delay_s: float | None = None, reverse: bool = False) -> JaegerPaths:
    """``plan`` (complete or partial, with configurations) as jaeger's trajectory (module docstring).

    Parameters
    ----------
    problem, plan : the problem and a complete or partial plan of it (configurations; on the
        plan's ``lattice`` when it names one); a partial plan's robots off target end at their
        starts.
    rpm : joint speed (RPM of the output shaft, 6°/s each); default the instrument's.
    acceleration : joint acceleration limit (deg/s²); None: none (every move at constant speed).
    start_delay_s : seconds before the first motion (default the instrument's, else 0).
    reverse : the path back, from the targets to the starts.

    Raises
    ------
    InputError
        A plan that is neither complete nor partial, or a limit out of range (naming it).
    """
    if plan.status not in ("complete", "partial") or not plan.configurations:
        raise InputError(f"a jaeger trajectory needs a complete or partial plan with configurations, got status "
                         f"{plan.status!r}", value=plan.status, where="plan")
    speed, accel, delay = jaeger_limits(problem, rpm, acceleration, start_delay_s)
    on = problem if plan.lattice is None or tuple(plan.lattice) == problem.kinematics.shape else \
        at_lattice(problem, plan.lattice)
    angles = continuous_angles(on, plan.configurations)
    timing = plan_timing(on, plan.configurations, speed, angles, _move_time(speed, accel))
    total = timing.motion_time_s
    ends = (problem.angles_deg(problem.start),
            problem.angles_deg(partial_end(problem.start, problem.target, tuple(plan.off_target), folded_ends(problem))))
    names = [j.name for j in problem.kinematics.joints]
    moves: list[list[tuple[float, float, int]]] = [[] for _ in range(problem.n)]
    for k, p, t0, t1 in zip(timing.step.tolist(), timing.robot.tolist(), timing.start.tolist(), timing.end.tolist()):
        moves[p].append((t0, t1, k))
    paths: dict[str, dict[str, list[list[float]]]] = {}
    fastest, count = 0.0, 0
    for p, key in enumerate(positioner_keys(problem)):
        if p in problem.held:  # offline: jaeger refuses a trajectory for a disabled positioner
            continue
        robot = {}
        for j, name in enumerate(names):
            pts = [(0.0, float(angles[0, p, j]))]
            for t0, t1, k in moves[p]:
                a0, a1 = float(angles[k, p, j]), float(angles[k + 1, p, j])
                tau, s = _profile(t1 - t0, speed, accel)
                pts += [(t0 + f * (t1 - t0), a0 + g * (a1 - a0)) for f, g in zip(tau.tolist(), s.tolist())
                        if t0 + f * (t1 - t0) > pts[-1][0]]
            if total > pts[-1][0]:
                pts.append((total, pts[-1][1]))
            arr = np.array(pts)
            if reverse:
                arr = np.stack([total - arr[::-1, 0], arr[::-1, 1]], axis=1)
            for i, want in ((0, ends[1 if reverse else 0][p, j]), (-1, ends[0 if reverse else 1][p, j])):
                if abs(arr[i, 1] - want) < 1e-6:  # exactly the problem's start and target angles
                    arr[i, 1] = want
            arr = _simplified(arr, speed)
            if len(arr) > 1:
                fastest = max(fastest, float(np.max(np.abs(np.diff(arr[:, 1]) / np.diff(arr[:, 0])))))
            count += len(arr)
            robot[name] = [[float(a), float(t) + delay] for t, a in arr]
        paths[key] = robot
    if fastest > speed * (1 + 1e-9):
        raise InputError(f"the export would move a joint at {fastest:.6g} deg/s, faster than {speed:g} deg/s",
                         value=fastest, where="rpm")
    return JaegerPaths(paths, total + delay, speed, fastest, accel, delay, count)


def write_jaeger(path: str | Path, paths: JaegerPaths, inputs: tuple = ()) -> Path:
    """Write ``paths`` to ``path`` atomically, never over one of ``inputs``, a link or a FIFO."""
    check_output(path, inputs, what=str(path))
    return atomic_write_text(path, json.dumps(paths.to_json()) + "\n")
