"""The validator's check of a repair phase: the rule of :mod:`.repair_phase`, with the validator's own geometry.

The repair phase ``c_0 = start, …, c_k`` of a plan from a colliding start is valid when

- every robot in ``repair.moved`` is a member of a pair colliding at the start and is not
  held (offline or fixed), and no other robot moves;
- on each step ``a_j + t·Δ_j`` (joint angles, ``t ∈ [0, 1]``), a pair colliding at ``t = 0``
  keeps ``d(t) ≥ d(0) − 10⁻⁶ mm``, and every other pair (robots, or a robot and a fixed
  obstacle) keeps ``d(t) ≥ r_a + r_b`` (up to the validator's :data:`~.validate_motion.TIE`);
- ``c_k`` is collision-free, and no robot touches an obstacle at the start.

Distances are the validator's (:class:`~.validate_motion.Bodies`, Ericson's segment
distance), each step sampled and bisected with the pair's Lipschitz bound as for any step
(:func:`~.validate_motion.step_distances`), here against a threshold per pair: its
distance at the step's beginning where it collides there.  None of the planner's geometry
is used.

Timed trajectories of such a plan (``solve --speed``) obey the same rule: their poses at
the union of their breakpoint times, up to the first at which they reach ``c_k``
(:func:`repair_end`), are a repair phase (:func:`check_timed_repair`; between breakpoints
every joint turns linearly in time, hence in angle), and from that time on
(:func:`trajectories_from`) they are the trajectories of the plan from ``c_k``.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .validate_motion import TIE, TOLERANCE, Bodies, MotionCheck, pieces_distances

__all__ = ["check_repair_phase", "check_timed_repair", "repair_end", "trajectories_from", "CLOSER_TOLERANCE"]

#: how much closer (mm) a colliding pair may come on a repair step: the bisection's own depth
CLOSER_TOLERANCE = TOLERANCE


def check_repair_phase(problem, bases: np.ndarray, moved: tuple[int, ...], count: int,
                       step: Callable[[int], tuple[np.ndarray, np.ndarray]], resolution: float,
                       problems: list[str]) -> MotionCheck:
    """Check the repair phase of ``count`` configurations (module docstring).

    Parameters
    ----------
    problem : Problem
        The problem, whose start may collide.
    bases : numpy.ndarray
        The robots' bases ``(N, 2)`` in mm, as the validator rebuilt them.
    moved : tuple of int
        PLAN.json's ``repair.moved``.
    count : int
        Configurations in the repair phase (``repair.steps + 1``).
    step : callable
        ``step(j)``: the angles ``(N, J)`` (degrees) of configuration ``j`` and the turn to
        configuration ``j + 1``.
    resolution : float
        The first sampling step (mm) of :func:`~.validate_motion.pieces_distances`.
    problems : list of str
        Each broken rule is appended as one line.

    Returns
    -------
    MotionCheck
        ``collisions``: steps and pairs breaking the rule; the pairs left undecided.
    """
    bodies = Bodies(problem, bases)
    ia, ib = bodies.pairs()
    need = bodies.buffers[ia] + bodies.buffers[ib]
    n, found, unsure, depth = bodies.n, 0, 0, 0.0
    a0, _ = step(0)
    d_start = _static(bodies, bodies.pad(a0), ia, ib, need, resolution)
    hit = d_start < need - TIE
    colliding = set(ia[hit & (ib < n)].tolist()) | set(ib[hit & (ib < n)].tolist())
    stray = sorted(set(moved) - colliding)
    if stray:
        problems.append(f"repair: positioners {stray} are in no pair colliding at the start, yet listed as moved")
    held = sorted(set(moved) & set(getattr(problem, "held", {}) or {}))
    if held:
        problems.append(f"repair: positioners {held} are held (offline or fixed) but listed as moved")
    if np.any(hit & (ib >= n)):
        h = int(np.nonzero(hit & (ib >= n))[0][0])
        problems.append(f"repair: positioner {int(ia[h])} collides with obstacle {int(ib[h]) - n} at the start "
                        f"(only collisions between robots are repaired)")
    for j in range(count - 1):
        a0, turn = step(j)
        movers = np.nonzero(np.any(turn != 0, axis=1))[0]
        outside = sorted(set(movers.tolist()) - set(moved))
        if outside:
            problems.append(f"repair step {j}->{j + 1}: positioners {outside} move but are not in repair.moved")
        a0, turn = bodies.pad(a0), bodies.pad(turn)
        begin = _static(bodies, a0, ia, ib, need, resolution)
        closer = begin < need - TIE
        want = np.where(closer, begin - CLOSER_TOLERANCE, need - TIE)
        dmin, u, deep = _step_distances(bodies, a0, turn, ia, ib, want, resolution)
        unsure, depth = unsure + u, max(depth, deep)
        for h in np.nonzero(dmin < want)[0]:
            found += 1
            who = (f"positioners {int(ia[h])} and {int(ib[h])}" if ib[h] < n
                   else f"positioner {int(ia[h])} and obstacle {int(ib[h]) - n}")
            problems.append(f"repair step {j}->{j + 1}: {who} come to {dmin[h]:.6f} mm, closer than "
                            + (f"their {begin[h]:.6f} mm at the step's beginning (they collide there)" if closer[h]
                               else f"their buffers' sum {need[h]:.6f} mm"))
    last, _ = step(count - 1)
    d_end = _static(bodies, bodies.pad(last), ia, ib, need, resolution)
    left = np.nonzero(d_end < need - TIE)[0]
    if len(left):
        h = int(left[0])
        problems.append(f"repair: configuration {count - 1}, the repair phase's last, still collides (positioners "
                        f"{int(ia[h])} and {int(ib[h]) if ib[h] < n else 'obstacle ' + str(int(ib[h]) - n)}; "
                        f"{len(left)} pairs)")
    return MotionCheck(found + len(left), float(np.min(d_end - need, initial=np.inf)), [], unsure, depth)


def _static(bodies: Bodies, angles: np.ndarray, ia: np.ndarray, ib: np.ndarray, need: np.ndarray,
            resolution: float) -> np.ndarray:
    """Distances (mm) of the pairs ``(ia, ib)`` at the padded ``angles``."""
    return _step_distances(bodies, angles, np.zeros_like(angles), ia, ib, need, resolution)[0]


def _step_distances(bodies: Bodies, a0: np.ndarray, turn: np.ndarray, ia: np.ndarray, ib: np.ndarray,
                    need: np.ndarray, resolution: float) -> tuple[np.ndarray, int, float]:
    """One step ``a0 + t·turn`` (padded angles, degrees): each pair's least distance (mm), the
    pairs left open and the deepest collision they could hide (:func:`~.validate_motion.pieces_distances`)."""
    dmin, _, unsure, deep = pieces_distances(bodies, a0[None], turn[None], ia, ib, need, resolution)
    return dmin[0], int(unsure[0]), float(deep[0])


def check_timed_repair(problem, bases: np.ndarray, moved: tuple[int, ...], poses: np.ndarray, resolution: float,
                       problems: list[str]) -> MotionCheck:
    """:func:`check_repair_phase` of the trajectories' poses ``(U, N, J)`` (degrees, continuous
    angles) up to the repair phase's end, each step their literal difference."""
    def step(j: int) -> tuple[np.ndarray, np.ndarray]:
        return poses[j], (poses[j + 1] - poses[j] if j + 1 < len(poses) else np.zeros_like(poses[j]))
    return check_repair_phase(problem, bases, moved, len(poses), step, resolution, problems)


def repair_end(poses: np.ndarray, end_deg: np.ndarray, wraps: np.ndarray, tol: float, problems: list[str]) -> int:
    """The first of the trajectories' poses ``(U, N, J)`` within ``tol`` degrees of the repair
    phase's last configuration ``end_deg`` ``(N, J)`` (modulo 360 where ``wraps``); the last
    pose, and a problem, when none is.

    >>> repair_end(np.array([[[0.0]], [[90.0]], [[450.0]]]), np.array([[90.0]]), np.array([[True]]), 1e-6, [])
    1
    """
    d = poses - end_deg
    d = np.where(wraps, np.mod(d + 180.0, 360.0) - 180.0, d)
    reached = np.nonzero(np.all(np.abs(d) <= tol, axis=(1, 2)))[0]
    if len(reached):
        return int(reached[0])
    problems.append("the trajectories never reach the repair phase's last configuration (configurations[repair.steps])")
    return len(poses) - 1


def trajectories_from(trajs: list[dict[str, np.ndarray]], t: float) -> list[dict[str, np.ndarray]]:
    """Each joint's trajectory ``(K, 2) [t_s, deg]`` from time ``t`` (s) on: its angle at ``t``
    (held before its first breakpoint and after its last), then its later breakpoints."""
    return [{name: np.vstack([[t, np.interp(t, a[:, 0], a[:, 1])], a[a[:, 0] > t]]) for name, a in robot.items()}
            for robot in trajs]
