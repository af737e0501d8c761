"""Independent geometric validation of a plan (what ``supcoord check`` runs).

A plan is a motion of every robot's joints from the start to the target, given in one of
three ways (``docs/formats.md``, PLAN.json):

- ``configurations`` ``c_0, …, c_T`` (lattice indices), each turned into joint angles by
  :meth:`Problem.angles_deg` (each robot's own lattice), a step ``c_k → c_{k+1}`` turning
  every joint linearly in angle by one lattice step at most (the short way round where it
  wraps).  Valid when ``c_0 = start``, ``c_T = target``, ``makespan = T``, every position
  is inside the joints' ranges, every joint moves at most one step per configuration, the
  ``events`` (when given) are move events of this problem (``v3``/``w3`` rotary,
  ``va3``/``wa3``/``vb3``/``wb3`` alpha-beta, positioners counted from 0) whose net effect
  from ``start`` is the last configuration (their order is not checked), and the
  ``angles_deg`` (when given besides) are those of the configurations (to 1e-6°, modulo
  360 where a joint wraps);
- ``angles_deg`` alone: poses ``θ_0, …, θ_T`` (degrees), a step turning each joint linearly
  from ``θ_k`` to ``θ_{k+1}``, the short way round where the joint wraps;
- ``trajectories`` alone: per robot and joint, breakpoints ``[t_s, deg]`` linear in time
  between them (a joint holds its first angle before its first breakpoint and its last
  after its last); the poses at the union of all breakpoint times are the steps (linear in
  time, hence in angle, between them).  Given besides configurations or angles, the
  trajectories are checked as a motion of their own too (problems prefixed
  ``trajectories:``), and ``motion_time_s`` (when given) must be their last time.

For angles and trajectories: the first pose is the start's angles and the last the
target's within 1e-6° (modulo 360 where the joint wraps), and every angle is inside the
joint's range (``alpha_range`` where alpha has hard stops, ``beta_range``).  In every case
no robot collides at any time of any step, ``θ_k + t·Δθ_k``, ``t ∈ [0, 1]``: neither a
neighbour (``dist(S_a(t), S_b(t)) ≥ r_a + r_b``) nor a fixed obstacle
(``dist(S_p(t), O) ≥ r_p + r_O``), ``S_p`` robot ``p``'s colliding segment at those angles;
an offline robot (``problem.held``) never leaves its angles and no robot under a joint rule
(``problem.joint_rules``) enters its forbidden half-plane ``β < c0 + c1·α``.  A step that
turns a joint by more than a full turn is checked one turn at a time (the same motion); one
of more than :data:`~.validate_motion.MAX_TURNS` turns is reported and not checked.

A plan from a colliding start carries ``repair`` (:mod:`.repair_phase`): its first
``repair.steps`` steps are checked by the repair rule (:mod:`.validate_repair`: only robots of
colliding pairs move, a colliding pair never comes closer, no new collision, collision-free at
the end), the rest as a plan from the repair phase's last configuration (trajectories: once they reach it).

*Collides* is ``dist < r_a + r_b`` (touching at exactly the sum is free), the definition
the collision tables use; an overlap of less than :data:`TIE` (1e-9 mm) is taken for the
rounding of an exact touch and not reported, so that the tables' and the validator's
double-precision formulas agree on touching arms.  Each step's time axis is first sampled
so that no point of a colliding segment moves more than ``resolution/2`` mm between samples
(default ``resolution`` = 0.05 mm); then every interval between two samples whose distances
do not settle it is **bisected**: with ``L`` the pair's travel bound (``d(t)`` is
``L``-Lipschitz, :mod:`.validate_motion`, which holds the validator's geometry), the least distance over an interval ``[t0, t1]``
is at least ``(d(t0) + d(t1) − L·(t1 − t0))/2``, so an interval is free once that bound
reaches ``r_a + r_b``, and a sample below it is a collision.  Bisection stops when an
interval's bound is within :data:`TOLERANCE` (1e-6 mm) of deciding, or when a pair has
more than :data:`MAX_OPEN` open intervals in one step (it touches along a stretch, at
exactly ``r_a + r_b``, which no sampling settles); such pairs are accepted and reported:
``undecided`` counts them and ``undecided_depth`` bounds how deep a collision they could
hide (a collision deeper than that is always found, whatever the resolution).

This module is deliberately *independent* of the planner and of the collision tables:
of the kinematics it reads only each robot's numbers (the chain of its arms, its reach,
:meth:`Problem.angles_deg`) and evaluates them with its own code (:mod:`.validate_motion`); it rebuilds a hex layout from
``rings`` and ``pitch`` by another construction (axial lattice coordinates sorted by
ring, then by polar angle) and reports a base that differs from the problem's, uses
another segment-distance algorithm (closest points of two segments by clamped
parameters, Ericson §5.1.9), its own neighbour bound ``|x_a − x_b| < reach_a + reach_b +
2·max r``, and its own reading of trajectories, so that it can catch their bugs.

Result: a :class:`ValidationResult`, whose :meth:`~ValidationResult.to_json` is ``{"valid",
"collisions", "at_target", "problems", "steps", "min_clearance", "incidents", "undecided",
"undecided_depth"}`` (and ``"motion_time_s"``, the last breakpoint time, when the plan has
trajectories), what ``supcoord check --json`` prints, where ``collisions`` counts (step, pair)
incidents, ``at_target`` the positioners whose last position is their target,
``min_clearance`` the least ``dist − (r_a + r_b)`` seen, and ``incidents`` lists the first
:data:`MAX_PROBLEMS` collisions as ``{"step": k, "positioners": [a, b], "t": t,
"distance": d, "required": r_a + r_b}`` (``t ∈ [0, 1]`` the time of the least distance
within step ``k → k+1``; a robot against an obstacle: ``"positioners": [p]`` and
``"obstacle": o``), which is what ``supcoord check --figure`` draws.

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.9.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np

from ..errors import InputError
from .consistency import check_problem, plan_defects
from .plan import Plan
from .problem import Problem
from .refine import at_lattice
from .validate_partial import at_whole_target, partial_problem
from .validate_repair import check_repair_phase, check_timed_repair, repair_end, trajectories_from
from .validation_result import Incident, ValidationResult
from .validate_motion import MAX_OPEN, TIE, TOLERANCE, MotionCheck, MotionChecker, segment_distance_ericson

__all__ = ["validate_plan", "ValidationResult", "segment_distance_ericson", "hex_bases_by_angle", "trajectory_poses",
           "MAX_PROBLEMS", "TOLERANCE", "RESOLUTION_RANGE", "MAX_OPEN", "TIE", "ANGLE_TOL"]

#: how many individual problems are listed before "... and N more"
MAX_PROBLEMS = 50
#: accepted first sampling steps (mm): finer only costs memory, coarser only bisection work
RESOLUTION_RANGE = (1e-4, 100.0)
#: degrees within which a plan's angles must meet the start, the target and the joint ranges
ANGLE_TOL = 1e-6


def hex_bases_by_angle(rings: int, pitch: float) -> np.ndarray:
    """Hex layout of ``docs/formats.md`` built another way than :func:`supcoord.geometry.layout.hex_grid`.

    Every axial lattice point ``p·(a + b/2, b·√3/2)`` with hex distance
    ``(|a| + |b| + |a + b|)/2 ≤ R``, sorted by that distance, then by polar angle in
    ``[0, 2π)`` (the ring's corner on ``+x`` first, counter-clockwise).

    >>> hex_bases_by_angle(1, 2.0).round(3).tolist()[:3]
    [[0.0, 0.0], [2.0, 0.0], [1.0, 1.732]]
    """
    a, b = (g.ravel() for g in np.meshgrid(np.arange(-rings, rings + 1), np.arange(-rings, rings + 1)))
    ring = (np.abs(a) + np.abs(b) + np.abs(a + b)) // 2
    a, b, ring = a[ring <= rings], b[ring <= rings], ring[ring <= rings]
    xy = pitch * np.stack([a + b / 2.0, b * math.sqrt(3) / 2.0], axis=-1)
    angle = np.mod(np.arctan2(b * math.sqrt(3) / 2.0, a + b / 2.0), 2 * math.pi)
    angle = np.where(ring == 0, 0.0, np.where(angle > 2 * math.pi - 1e-9, 0.0, angle))
    return xy[np.lexsort((angle, ring))]


def _bases(problem: Problem, problems: list[str]) -> np.ndarray:
    """The bases to check against: rebuilt from a hex layout's numbers, else the given points."""
    layout = problem.layout
    if layout.get("kind") != "hex":
        return np.asarray(layout.get("xy", problem.bases), float).reshape(-1, 2)
    own = hex_bases_by_angle(int(layout["rings"]), float(layout["pitch"]))
    if own.shape != problem.bases.shape:
        problems.append(f"layout: {len(problem.bases)} bases, but a hex grid of {layout['rings']} rings has {len(own)}")
        return problem.bases
    off = np.nonzero(np.hypot(*(own - problem.bases).T) > 1e-6 * max(1.0, float(layout["pitch"])))[0]
    if len(off):
        i = int(off[0])
        problems.append(f"layout: base of positioner {i} is {problem.bases[i].round(4).tolist()} but the hex "
                        f"ordering of formats.md puts it at {own[i].round(4).tolist()} ({len(off)} bases differ)")
    return own


_EVENT = re.compile(r"(va|wa|vb|wb|v|w)(\d+)")
_JOINT = {"rotary": {"v": (0, 1), "w": (0, -1)},
          "alpha-beta": {"va": (0, 1), "wa": (0, -1), "vb": (1, 1), "wb": (1, -1)}}


def _check_events(kind: str, events: list[str], start: np.ndarray, last: np.ndarray, steps: np.ndarray,
                  wraps: np.ndarray, problems: list[str]) -> None:
    """Event names of this kinematics, and their net effect from ``start`` equal to ``last``."""
    net = np.zeros_like(start)
    for k, name in enumerate(events):
        m = _EVENT.fullmatch(name)
        p = int(m.group(2)) if m else -1
        if m is None or m.group(1) not in _JOINT[kind] or not 0 <= p < len(start):
            problems.append(f"events[{k}] = {name!r} is not a move event of this {kind} problem with "
                            f"{len(start)} positioners ({', '.join(f'{e}P' for e in _JOINT[kind])}, P in "
                            f"[0, {len(start) - 1}])")
            return
        joint, delta = _JOINT[kind][m.group(1)]
        net[p, joint] += delta
    end = start + net
    end = np.where(wraps, np.mod(end, steps), end)
    off = np.nonzero(np.any(end != last, axis=1))[0]
    if len(off):
        problems.append(f"the {len(events)} events do not lead from the start to the last configuration "
                        f"(positioners {_ids(off)} differ)")


def validate_plan(problem: Problem, plan: Plan, resolution: float = 0.05) -> ValidationResult:
    """Check a plan against its problem geometrically, independently of the planner.

    The rule is the module docstring's: start to target, joints in range, no collision at
    any time of any step (sampled, then bisected to 1e-6 mm).  A bad plan is reported in
    the result, never raised.

    Parameters
    ----------
    problem : Problem
        The problem the plan claims to solve (lengths in mm, angles in degrees).
    plan : Plan
        Configurations (lattice indices), poses (degrees) or trajectories (``[t_s, deg]``).
    resolution : float, default 0.05
        First sampling step in mm (within :data:`RESOLUTION_RANGE`): no point of a robot
        moves farther between samples; the verdict does not depend on it.

    Returns
    -------
    ValidationResult
        ``valid`` (bool), ``collisions`` (colliding step and pair incidents), ``at_target``
        (robots whose last position is their target), ``problems`` (one line each, at most
        :data:`MAX_PROBLEMS`), ``steps``, ``min_clearance`` (mm, or None), ``incidents``
        (the first collisions: step, positioners, time ``t`` in [0, 1] of the step,
        distance and required distance in mm), ``undecided`` and ``undecided_depth`` (mm);
        ``motion_time_s`` (s) when the plan has trajectories; :meth:`~ValidationResult.to_json`
        is what ``supcoord check --json`` prints.

    Raises
    ------
    InputError
        ``plan`` is not a :class:`Plan`, ``problem`` not a consistent :class:`Problem`, or
        ``resolution`` out of range.

    Examples
    --------
    >>> from supcoord.problems import parse_problem, Plan
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 8.0, "steps": 4},
    ...                    "collision": {"buffer": 1.0}, "start": [0, 0], "target": [1, 0]})
    >>> r = validate_plan(p, Plan("complete", [p.start, p.target]))
    >>> r.valid, r.collisions, r.at_target, r.steps
    (True, 0, 2, 1)
    >>> validate_plan(p, Plan("complete", [p.start])).problems
    ['the last configuration is not the target (positioners 0 are not at target)']

    References
    ----------
    C. Ericson, *Real-Time Collision Detection*, 2005, §5.1.9; P. Hansen, B. Jaumard,
    S.-H. Lu, Global optimization of univariate Lipschitz functions, Math. Prog. 55, 1992.
    """
    _check_arguments(problem, plan, resolution)
    problems: list[str] = plan_defects(plan, problem.n, problem.kinematics.n_joints)
    if problems:  # a malformed plan is an invalid one
        return _result(False, 0, 0, problems[:1], 0, None)
    if plan.lattice is not None and tuple(plan.lattice) != problem.kinematics.shape:
        try:  # planned on a finer lattice: the same problem re-derived there (.refine)
            problem = at_lattice(problem, plan.lattice)
        except InputError as exc:
            return _result(False, 0, 0, [exc.one_line()], max(0, len(plan.configurations) - 1), None)
    if plan.repair is not None:  # from a colliding start: the repair phase, then a plan from its end
        return _validate_repaired(problem, plan, resolution)
    whole = problem
    if plan.status == "partial":  # checked as a complete plan of the problem ending where it says
        problem = partial_problem(problem, plan, problems)
    motion = _read_motion(problem, plan, problems)
    if isinstance(motion, ValidationResult):  # refused: the result says why
        return motion
    checker = MotionChecker(problem, _bases(problem, problems), resolution, MAX_PROBLEMS)
    confs, poses, trajs = motion.confs, motion.poses, motion.trajs
    if confs:
        at_target, found = _check_configurations(problem, plan, confs, poses, checker, problems)
        n_steps = len(confs) - 1
    elif poses:
        at_target, found = _check_poses(problem, plan, poses, checker, problems)
        n_steps = len(poses) - 1
    if trajs is not None:
        found, end, alone = _check_trajectories(problem, plan, trajs, found if confs or poses else None, checker,
                                                problems)
        if alone is not None:
            at_target, n_steps = alone
    if problem is not whole:  # robots at their own targets, not at the ends the partial plan lists
        at_target = at_whole_target(whole, problem, confs, at_target)
    result = _result(not problems, found.collisions, at_target, problems, n_steps, found.clearance, found.incidents,
                     (found.undecided, found.depth))
    if trajs is not None:
        result = replace(result, motion_time_s=end)
    return result


def _validate_repaired(problem: Problem, plan: Plan, resolution: float) -> ValidationResult:
    """A plan with a repair phase ``c_0 … c_k`` (:mod:`.validate_repair`), then ``c_k … c_T``
    checked as a plan from ``c_k``; the events and makespan over the whole plan."""
    problems: list[str] = []
    confs = [np.asarray(c, dtype=np.int64) for c in plan.configurations]
    k, kin = plan.repair.steps, problem.kinematics
    steps, wraps = np.array([j.steps for j in kin.joints]), np.array([j.wraps for j in kin.joints])
    if k >= len(confs):
        problems.append(f"repair.steps is {k}: no configuration after the repair phase ({len(confs)} in all)")
        return _result(False, 0, 0, problems, max(0, len(confs) - 1), None)
    out = [j for j, c in enumerate(confs) if np.any((c < 0) | (c >= steps))]
    if out or not np.array_equal(confs[0], problem.start):
        problems.append(f"configurations[{out[0]}] is out of the joint ranges" if out else
                        "configurations[0] is not the start")
        return _result(False, 0, 0, problems, len(confs) - 1, None)
    if plan.angles_deg:
        _check_angles_match(problem, confs, problem.angles_deg(np.stack(confs)), list(plan.angles_deg), problems)
    _check_held_and_rules(problem, lambda p: problem.kin(p).joint_angles_deg(np.array([c[p] for c in confs[:k + 1]])),
                          "repair", problems)

    def step(j: int) -> tuple[np.ndarray, np.ndarray]:
        a0 = problem.angles_deg(confs[j])
        if j >= k:
            return a0, np.zeros_like(a0)
        return a0, problem.angles_deg(confs[j] + _step_delta(confs[j], confs[j + 1], steps, wraps, j, problems)) - a0

    bases = _bases(problem, problems)
    fixed = check_repair_phase(problem, bases, plan.repair.moved, k + 1, step, resolution, problems)
    tail_trajs, trajs = plan.trajectories, _trajectory_arrays(plan.trajectories, [j.name for j in kin.joints], problem.n)
    if trajs is not None:  # timed: the repair rule until they reach configurations[k], then as any plan from there
        (times, poses), own = trajectory_poses(trajs), []
        b = repair_end(poses, problem.angles_deg(confs[k]), _wrapping(problem), ANGLE_TOL, own)
        _check_angle_poses(replace(problem, target=confs[k]), poses[:b + 1], "repair", own)
        _check_held_and_rules(problem, lambda p: poses[:b + 1, p], "repair", own)
        fixed = fixed.plus(check_timed_repair(problem, bases, plan.repair.moved, poses[:b + 1], resolution, own))
        problems += ["trajectories: " + p for p in own]
        tail_trajs = trajectories_from(trajs, float(times[b]))
    tail = replace(plan, configurations=confs[k:], makespan=len(confs) - 1 - k, lower_bound=None, events=[],
                   stats={}, angles_deg=list(plan.angles_deg[k:]), trajectories=tail_trajs, repair=None)
    rest = validate_plan(dataclasses.replace(problem, start=confs[k]), tail, resolution)
    problems += [f"after the repair phase (step {k} on): {p}" for p in rest.problems]
    if plan.events:
        _check_events(kin.kind, plan.events, problem.start, confs[-1], steps, wraps, problems)
    if plan.makespan is not None and plan.makespan != len(confs) - 1:
        problems.append(f"makespan is {plan.makespan} but the plan has {len(confs) - 1} steps")
    clearance = min(fixed.clearance, rest.min_clearance if rest.min_clearance is not None else math.inf)
    incidents = [dataclasses.replace(i, step=i.step + k) for i in rest.incidents]
    return replace(_result(not problems, fixed.collisions + rest.collisions, rest.at_target, problems, len(confs) - 1,
                   clearance, incidents, (fixed.undecided + rest.undecided, max(fixed.depth, rest.undecided_depth))),
                   motion_time_s=rest.motion_time_s)


def _check_arguments(problem: Any, plan: Any, resolution: Any) -> None:
    """Raise :class:`InputError` unless a :class:`Plan`, a consistent :class:`Problem` and a
    resolution in :data:`RESOLUTION_RANGE`."""
    if not isinstance(plan, Plan):
        raise InputError(f"validate_plan needs a Plan, got {type(plan).__name__}", value=None, where="plan")
    check_problem(problem)  # a Problem, and still consistent
    lo, hi = RESOLUTION_RANGE
    if isinstance(resolution, bool) or not isinstance(resolution, (int, float)) or not lo <= resolution <= hi:
        raise InputError(f"resolution must be a number of mm in [{lo:g}, {hi:g}], got {resolution!r}",
                         value=resolution, where="resolution")


def _check_trajectories(problem: Problem, plan: Plan, trajs: list[dict[str, np.ndarray]],
                        found: MotionCheck | None, checker: MotionChecker,
                        problems: list[str]) -> tuple[MotionCheck, float, tuple[int, int] | None]:
    """The trajectories as a motion: alone (``found`` None), or besides configurations or poses
    that found ``found`` (their problems then prefixed ``trajectories:``).  Returns what the
    checks found, the last breakpoint time (s; ``motion_time_s`` must be it) and, alone, the
    robots at target and the steps."""
    times, poses = trajectory_poses(trajs)
    if found is None:
        at_target, found = _check_trajectory_motion(problem, poses, checker, problems)
        alone: tuple[int, int] | None = (at_target, len(times) - 1)
    else:
        own: list[str] = []
        found = found.plus(_check_trajectory_motion(problem, poses, checker, own)[1])
        problems.extend(p if p.startswith("trajectories: ") else "trajectories: " + p for p in own)
        alone = None
    end = float(max(float(t[-1, 0]) for robot in trajs for t in robot.values()))
    if plan.motion_time_s is not None and abs(plan.motion_time_s - end) > 1e-9 * max(1.0, end):
        problems.append(f"motion_time_s is {plan.motion_time_s!r} but the trajectories end at t = {end!r} s")
    return found, end, alone


@dataclass(frozen=True)
class _Motion:
    """A plan's motion as arrays: configurations ``(N, J)`` ints, poses ``(N, J)`` degrees, and
    per robot ``{joint: (K, 2) [t_s, deg]}`` trajectories (None: none, or not this problem's)."""

    confs: list[np.ndarray]
    poses: list[np.ndarray]
    trajs: list[dict[str, np.ndarray]] | None


def _read_motion(problem: Problem, plan: Plan, problems: list[str]) -> _Motion | ValidationResult:
    """The plan's motion, or the result for one of the wrong shape or with no pose at all (a
    plan that is not complete is reported in ``problems`` and still checked)."""
    motion = _Motion([np.asarray(c, dtype=np.int64) for c in plan.configurations],
                     [np.asarray(a, dtype=float) for a in plan.angles_deg],
                     _trajectory_arrays(plan.trajectories, [j.name for j in problem.kinematics.joints], problem.n))
    shape = (problem.n, problem.kinematics.n_joints)
    for name, seq in (("configurations", motion.confs), ("angles_deg", motion.poses)):
        wrong = [k for k, c in enumerate(seq) if c.shape != shape]
        if wrong:
            problems.append(f"{name}[{wrong[0]}] has shape {list(seq[wrong[0]].shape)}, not {list(shape)} "
                            f"({problem.n} positioners, {shape[1]} joints): a plan for another problem?")
            return _result(False, 0, 0, problems, max(0, len(seq) - 1), None)
    bad = [k for k, a in enumerate(motion.poses) if not np.all(np.isfinite(a))]
    if bad:
        problems.append(f"angles_deg[{bad[0]}] holds an angle that is not a finite number")
        return _result(False, 0, 0, problems, max(0, len(motion.poses) - 1), None)
    if motion.trajs is None and plan.trajectories is not None:
        problems.append(f"trajectories must give each of {problem.n} positioners the joints "
                        f"{[j.name for j in problem.kinematics.joints]}, each a non-empty list of [t_s, deg] in "
                        f"increasing time: a plan for another problem?")
        return _result(False, 0, 0, problems, 0, None)
    if plan.status not in ("complete", "partial"):
        problems.append(f"plan status is {plan.status!r}" + (f": {plan.reason}" if plan.reason else ""))
    if not motion.confs and not motion.poses and motion.trajs is None:
        problems.append("the plan has no configurations")
        return _result(False, 0, int(np.sum(np.all(problem.start == problem.target, axis=1))), problems, 0, None)
    return motion


def _check_configurations(problem: Problem, plan: Plan, confs: list[np.ndarray], poses: list[np.ndarray],
                          checker: MotionChecker, problems: list[str]) -> tuple[int, MotionCheck]:
    """A motion given by lattice configurations (and the angles given besides them): the robots
    at target and what the geometric check found."""
    kin = problem.kinematics
    steps = np.array([j.steps for j in kin.joints])
    wraps = np.array([j.wraps for j in kin.joints])
    at_target = int(np.sum(np.all(confs[-1] == problem.target, axis=1)))
    _check_sequence(problem, plan, kin.kind, confs, steps, wraps, problems)
    # every configuration's angles and every step's end in one call each (each robot's own lattice)
    starts = problem.angles_deg(np.stack(confs))
    ends = problem.angles_deg(np.stack([c + _step_delta(c, c1, steps, wraps, k, [])
                                        for k, (c, c1) in enumerate(zip(confs, confs[1:] + confs[-1:]))]))
    if poses:
        _check_angles_match(problem, confs, starts, poses, problems)
    _check_held_and_rules(problem, lambda p: starts[:, p], "configurations", problems)

    def step(k: int) -> tuple[np.ndarray, np.ndarray]:
        a0 = starts[k]
        if k + 1 >= len(confs):
            return a0, np.zeros_like(a0)
        _step_delta(confs[k], confs[k + 1], steps, wraps, k, problems)  # its report, in the step's turn
        return a0, ends[k] - a0

    return at_target, checker.check(step, len(confs), "configuration 0", problems)


def _check_poses(problem: Problem, plan: Plan, poses: list[np.ndarray], checker: MotionChecker,
                 problems: list[str]) -> tuple[int, MotionCheck]:
    """A motion given by joint angles: each step the short way round where a joint wraps."""
    stacked = np.stack(poses)
    at_target = _check_angle_poses(problem, stacked, "angles_deg", problems)
    _check_held_and_rules(problem, lambda p: stacked[:, p], "angles_deg", problems)
    if plan.makespan is not None and plan.makespan != len(poses) - 1:
        problems.append(f"makespan is {plan.makespan} but the plan has {len(poses) - 1} steps")
    return at_target, checker.check(_pose_steps(poses, _wrapping(problem)), len(poses), "pose 0", problems)


def _check_trajectory_motion(problem: Problem, poses: np.ndarray, checker: MotionChecker,
                             problems: list[str]) -> tuple[int, MotionCheck]:
    """Trajectories' poses at their breakpoint times ``(U, N, J)``: start, target, ranges,
    offline robots and joint rules, then the steps between them (linear in time, hence in angle)."""
    at_target = _check_angle_poses(problem, poses, "trajectories", problems)
    _check_held_and_rules(problem, lambda p: poses[:, p], "trajectories", problems)
    return at_target, checker.check(_pose_steps(list(poses), None), len(poses), "pose 0", problems)


def _check_angles_match(problem: Problem, confs: list[np.ndarray], angles: np.ndarray, poses: list[np.ndarray],
                        problems: list[str]) -> None:
    """``angles_deg`` given besides the configurations must be theirs (``angles``)."""
    if len(confs) != len(poses):
        problems.append(f"angles_deg has {len(poses)} poses but configurations has {len(confs)}")
    for k, (c, a) in enumerate(zip(angles, poses)):
        bad = _angles_off(problem, a, c)
        if len(bad):
            problems.append(f"angles_deg[{k}] are not the angles of configurations[{k}] (positioners {_ids(bad)})")
            return


def _check_sequence(problem: Problem, plan: Plan, kind: str, confs: list[np.ndarray], steps: np.ndarray,
                    wraps: np.ndarray, problems: list[str]) -> None:
    """Start and target, the events' net effect, the makespan and the joint ranges."""
    if not np.array_equal(confs[0], problem.start):
        bad = np.nonzero(np.any(confs[0] != problem.start, axis=1))[0]
        problems.append(f"configurations[0] is not the start (positioners {_ids(bad)} differ)")
    if not np.array_equal(confs[-1], problem.target):
        bad = np.nonzero(np.any(confs[-1] != problem.target, axis=1))[0]
        problems.append(f"the last configuration is not the target (positioners {_ids(bad)} are not at target)")
    if plan.events:
        _check_events(kind, plan.events, problem.start, confs[-1], steps, wraps, problems)
    if plan.makespan is not None and plan.makespan != len(confs) - 1:
        problems.append(f"makespan is {plan.makespan} but the plan has {len(confs) - 1} steps")
    for k, c in enumerate(confs):
        out = np.nonzero(np.any((c < 0) | (c >= steps), axis=1))[0]
        if len(out):
            problems.append(f"configurations[{k}]: positioners {_ids(out)} are out of the joint ranges")


def _step_delta(c0: np.ndarray, c1: np.ndarray, steps: np.ndarray, wraps: np.ndarray, k: int,
                problems: list[str]) -> np.ndarray:
    """``c1 − c0`` the short way round where a joint wraps; a jump of more than one step is
    reported and clipped to one (the motion is still checked)."""
    delta = c1 - c0
    delta = np.where(wraps, (delta + steps // 2) % steps - steps // 2, delta)  # the short way round
    delta = np.where(wraps & (steps == 2) & (delta == -1), 1, delta)
    jumps = np.nonzero(np.any(np.abs(delta) > 1, axis=1))[0]
    if len(jumps):
        problems.append(f"step {k}->{k + 1}: positioners {_ids(jumps)} move a joint by more than one step")
        delta = np.clip(delta, -1, 1)
    return delta


def _wrapping(problem: Problem) -> np.ndarray:
    """``(N, J)``: does joint ``j`` of robot ``p`` wrap?"""
    return np.array([[j.wraps for j in problem.kin(p).joints] for p in range(problem.n)], dtype=bool).reshape(
        problem.n, problem.kinematics.n_joints)


def _short_way(d: np.ndarray) -> np.ndarray:
    return np.mod(d + 180.0, 360.0) - 180.0


def _pose_steps(poses: list[np.ndarray], wraps: np.ndarray | None) -> Callable[[int], tuple[np.ndarray, np.ndarray]]:
    """Steps between angle poses: literal differences, or the short way round where ``wraps``."""
    def step(k: int) -> tuple[np.ndarray, np.ndarray]:
        if k + 1 >= len(poses):
            return poses[k], np.zeros_like(poses[k])
        d = poses[k + 1] - poses[k]
        return poses[k], (d if wraps is None else np.where(wraps, _short_way(d), d))
    return step


def _angles_off(problem: Problem, got: np.ndarray, want: np.ndarray, rows: int | None = None) -> np.ndarray:
    """Rows (robots; or the poses of robot ``rows``) whose angles ``got`` differ from ``want`` by
    more than :data:`ANGLE_TOL` (modulo 360 where the joint wraps)."""
    d = got - want
    wraps = _wrapping(problem)
    d = np.where(wraps if rows is None else wraps[rows], _short_way(d), d)
    return np.nonzero(np.any(~(np.abs(d) <= ANGLE_TOL), axis=1))[0]


def _check_angle_poses(problem: Problem, poses: np.ndarray, name: str, problems: list[str]) -> int:
    """Start, target and joint ranges of angle poses ``(T+1, N, J)``; the robots at target."""
    bad = _angles_off(problem, poses[0], problem.angles_deg(problem.start))
    if len(bad):
        problems.append(f"{name}: the plan does not start at the start (positioners {_ids(bad)} are more than "
                        f"{ANGLE_TOL:g} deg off)")
    bad = _angles_off(problem, poses[-1], problem.angles_deg(problem.target))
    if len(bad):
        problems.append(f"{name}: the plan does not end at the target (positioners {_ids(bad)} are more than "
                        f"{ANGLE_TOL:g} deg off)")
    lo = np.full(poses.shape[1:], -np.inf)
    hi = np.full(poses.shape[1:], np.inf)
    for p in range(problem.n):
        k = problem.kin(p)
        for j, jt in enumerate(k.joints):
            rng = getattr(k, "alpha_range" if j == 0 else "beta_range", None) if k.kind == "alpha-beta" else None
            if not jt.wraps and rng is not None:
                lo[p, j], hi[p, j] = rng
    out = np.any((poses < lo - ANGLE_TOL) | (poses > hi + ANGLE_TOL), axis=2)
    for k in np.nonzero(out.any(axis=1))[0][:3]:
        problems.append(f"{name}: pose {k}: positioners {_ids(np.nonzero(out[k])[0])} are out of the joint ranges")
    return problem.n - len(bad)


def _check_held_and_rules(problem: Problem, robot_angles: Callable[[int], np.ndarray], name: str,
                          problems: list[str]) -> None:
    """Offline robots (``problem.held``) never leave their start angles; no robot under a joint
    rule (``problem.joint_rules``: ``β < c0 + c1·α`` forbidden, degrees) enters its forbidden
    half-plane (a step is linear in angle, so checking the poses checks the motion).
    ``robot_angles(p)``: robot ``p``'s angles at every pose ``(T+1, J)``."""
    held, rules = getattr(problem, "held", None) or {}, getattr(problem, "joint_rules", None) or {}
    start = problem.angles_deg(problem.start) if held else None
    moved = [p for p in sorted(held) if len(_angles_off(problem, robot_angles(p),
                                                        np.broadcast_to(start[p], (1, start.shape[1])), rows=p))]
    broken = [p for p in sorted(rules)
              if np.any((a := robot_angles(p))[:, 1] < rules[p][0] + rules[p][1] * a[:, 0] - ANGLE_TOL)]
    if moved:
        problems.append(f"{name}: offline positioners {_ids(moved)} move")
    if broken:
        problems.append(f"{name}: positioners {_ids(broken)} enter the forbidden region of their joint rule "
                        f"(beta < c0 + c1 * alpha)")


def _trajectory_arrays(trajs: Any, names: list[str], n: int) -> list[dict[str, np.ndarray]] | None:
    """The trajectories as ``{joint: (K, 2) array}`` per robot, or None (none, or not this problem's)."""
    if trajs is None or not isinstance(trajs, (list, tuple)) or len(trajs) != n:
        return None
    out = []
    for robot in trajs:
        if not isinstance(robot, dict) or set(robot) != set(names):
            return None
        try:
            arrays = {name: np.asarray(robot[name], dtype=float).reshape(-1, 2) for name in names}
        except (TypeError, ValueError):
            return None
        if any(len(a) == 0 or not np.all(np.isfinite(a)) or np.any(np.diff(a[:, 0]) <= 0) for a in arrays.values()):
            return None
        out.append(arrays)
    return out


def trajectory_poses(trajs: list[dict[str, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """The union of all breakpoint times and every robot's angles there ``(U, N, J)``, each
    joint linear in time between its breakpoints and held before the first and after the last."""
    names = list(trajs[0])
    times = np.unique(np.concatenate([a[:, 0] for robot in trajs for a in robot.values()]))
    poses = np.empty((len(times), len(trajs), len(names)))
    for p, robot in enumerate(trajs):
        for j, name in enumerate(names):
            poses[:, p, j] = np.interp(times, robot[name][:, 0], robot[name][:, 1])
    return times, poses


def _ids(idx: Any, limit: int = 10) -> str:
    idx = [int(i) for i in idx]
    text = ", ".join(map(str, idx[:limit]))
    return text + (f", ... ({len(idx)} in all)" if len(idx) > limit else "")


def _result(valid: bool, collisions: int, at_target: int, problems: list[str], steps: int,
            clearance: float | None, incidents: list[Incident] | None = None,
            undecided: tuple[int, float] = (0, 0.0)) -> ValidationResult:
    if len(problems) > MAX_PROBLEMS:
        problems = problems[:MAX_PROBLEMS] + [f"... and {len(problems) - MAX_PROBLEMS} more"]
    if clearance is not None and not math.isfinite(clearance):
        clearance = None
    return ValidationResult(bool(valid), int(collisions), int(at_target), problems, int(steps), clearance,
                            list(incidents or []), int(undecided[0]), float(undecided[1]))
