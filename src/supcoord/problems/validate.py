"""Independent geometric validation of a plan (what ``supcoord check`` runs).

A plan ``c_0, …, c_T`` is *valid* for a problem when

- ``c_0 = start`` and ``c_T = target``, the status is ``complete``, ``makespan = T``;
- every position is inside the joints' ranges, and between consecutive configurations
  every joint moves at most one step (cyclically where it wraps);
- the ``events`` (when given) are move events of this problem (``v3``/``w3`` rotary,
  ``va3``/``wa3``/``vb3``/``wb3`` alpha-beta, positioners counted from 0) whose net effect
  from ``start`` is the last configuration (their order is not checked: a plan may
  merge and reorder its single moves);
- no neighbour pair collides at any time of any step: with all moving joints
  interpolated together, ``c_k + t·(c_{k+1} − c_k)``, ``t ∈ [0, 1]``,
  ``∀k ∀(a, b) ∀t. dist(S_a(t), S_b(t)) ≥ r_a + r_b``.

*Collides* is ``dist < r_a + r_b`` (touching at exactly the sum is free), the definition
the collision tables use; an overlap of less than :data:`TIE` (1e-9 mm) is taken for the
rounding of an exact touch and not reported, so that the tables' and the validator's
double-precision formulas agree on touching arms.  Each step's time axis is first sampled so that no point of a
colliding segment moves more than ``resolution/2`` mm between samples (default
``resolution`` = 0.05 mm); then every interval between two samples whose distances do
not settle it is **bisected**: with ``L`` the pair's travel bound (``d(t)`` is
``L``-Lipschitz), the least distance over an interval ``[t0, t1]`` is at least
``(d(t0) + d(t1) − L·(t1 − t0))/2``, so an interval is free once that bound reaches
``r_a + r_b``, and a sample below it is a collision.  Bisection stops when an interval's
bound is within :data:`TOLERANCE` (1e-6 mm) of deciding, or when a pair has more than
:data:`MAX_OPEN` open intervals in one step (it touches along a stretch, at exactly
``r_a + r_b``, which no sampling settles); such pairs are accepted and reported:
``undecided`` counts them and ``undecided_depth`` bounds how deep a collision they could
hide (a collision deeper than that is always found, whatever the resolution).  This
module is deliberately *independent* of
:mod:`supcoord.geometry` (layout, kinematics, collision tables): it rebuilds a
hex layout from ``rings`` and ``pitch`` by another construction (axial lattice
coordinates sorted by ring, then by polar angle) and reports a base that differs from
the problem's, recomputes the arms from the PROBLEM.json numbers with the formulas of
``docs/formats.md``, uses another segment-distance algorithm (closest points of two
segments by clamped parameters, Ericson §5.1.9) and its own neighbour bound
``|x_a − x_b| < 2·Σ (arm lengths) + 2·max r``, so that it can catch their bugs.

Result: ``{"valid", "collisions", "at_target", "problems", "steps", "min_clearance",
"incidents", "undecided", "undecided_depth"}`` where ``collisions`` counts (step, pair) incidents, ``at_target`` the
positioners whose last position is their target, ``min_clearance`` the least
``dist − (r_a + r_b)`` seen, and ``incidents`` lists the first :data:`MAX_PROBLEMS`
collisions as ``{"step": k, "positioners": [a, b], "t": t, "distance": d,
"required": r_a + r_b}`` (``t ∈ [0, 1]`` the time of the least distance within step
``k → k+1``), which is what ``supcoord check --figure`` draws.

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.9.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from ..errors import InputError
from .plan import Plan
from .problem import Problem
from .validate_motion import MAX_OPEN, TOLERANCE, _arm, _close_pairs, _step_distances, segment_distance_ericson

__all__ = ["validate_plan", "segment_distance_ericson", "hex_bases_by_angle", "MAX_PROBLEMS", "TOLERANCE",
           "RESOLUTION_RANGE", "MAX_OPEN", "TIE"]

#: how many individual problems are listed before "... and N more"
MAX_PROBLEMS = 50
#: accepted first sampling steps (mm): finer only costs memory, coarser only bisection work
RESOLUTION_RANGE = (1e-4, 100.0)
#: depth (mm) of an overlap the validator attributes to rounding: arms that touch at exactly the
#: buffer sum (round-number layouts) come out 1e-15 mm either side of it in double precision,
#: differently in the planner's formulas and in these, so a touch is not reported as a collision
TIE = 1e-9


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


def validate_plan(problem: Problem, plan: Plan, resolution: float = 0.05) -> dict[str, Any]:
    """Check ``plan`` against ``problem`` geometrically (module docstring); never raises on a
    bad plan.  ``resolution`` (mm, within :data:`RESOLUTION_RANGE`) sets the first sampling;
    the verdict does not depend on it."""
    if not isinstance(problem, Problem) or not isinstance(plan, Plan):
        raise InputError(f"validate_plan needs a Problem and a Plan, got {type(problem).__name__} and "
                         f"{type(plan).__name__}", value=None)
    lo, hi = RESOLUTION_RANGE
    if isinstance(resolution, bool) or not isinstance(resolution, (int, float)) or not lo <= resolution <= hi:
        raise InputError(f"resolution must be a number of mm in [{lo:g}, {hi:g}], got {resolution!r}",
                         value=resolution, where="resolution")
    kin = problem.kinematics.to_json()
    steps = np.array([kin["steps"]] if kin["kind"] == "rotary" else [kin["alpha_steps"], kin["beta_steps"]])
    wraps = np.array([True] if kin["kind"] == "rotary" else [True, False])
    problems: list[str] = []
    shape = (problem.n, len(steps))
    confs = [np.asarray(c, dtype=np.int64) for c in plan.configurations]
    wrong = [k for k, c in enumerate(confs) if c.shape != shape]
    if wrong:
        problems.append(f"configurations[{wrong[0]}] has shape {list(confs[wrong[0]].shape)}, not {list(shape)} "
                        f"({problem.n} positioners, {len(steps)} joints): a plan for another problem?")
        return _result(False, 0, 0, problems, max(0, len(confs) - 1), None)
    last = confs[-1] if confs else problem.start
    at_target = int(np.sum(np.all(last == problem.target, axis=1)))
    if plan.status != "complete":
        problems.append(f"plan status is {plan.status!r}" + (f": {plan.reason}" if plan.reason else ""))
    if not confs:
        problems.append("the plan has no configurations")
        return _result(False, 0, at_target, problems, 0, None)
    _check_sequence(problem, plan, kin["kind"], confs, steps, wraps, problems)

    # neighbour pairs, from scratch: sum of arm lengths bounds each segment's distance from its base
    bases, buf = _bases(problem, problems), problem.buffers
    _, _, reach, incr = _arm(kin, np.zeros((1, len(steps))))
    ia, ib = _close_pairs(bases, 2 * reach + 2 * buf.max(initial=0.0))
    need = buf[ia] + buf[ib]

    collisions = undecided = 0
    depth = 0.0
    clearance = math.inf
    incidents: list[dict[str, Any]] = []
    for k in range(max(1, len(confs) - 1)):
        c0 = confs[k]
        c1 = confs[k + 1] if k + 1 < len(confs) else c0
        delta = _step_delta(c0, c1, steps, wraps, k, problems)
        # every point of a colliding segment moves at most reach·Σ|Δ_j|·incr_j (each joint turns
        # the segment about a point within `reach` of it)
        travel = reach * (np.abs(delta) @ incr)
        dmin, tmin, (unsure, deep) = _step_distances(kin, bases, c0, delta, ia, ib, travel, need - TIE, resolution)
        undecided += unsure
        depth = max(depth, deep)
        if len(dmin):
            clearance = min(clearance, float(np.min(dmin - need)))
        hits = np.nonzero(dmin < need - TIE)[0]
        collisions += len(hits)
        where = f"step {k}->{k + 1}" if len(confs) > 1 else "configuration 0"
        for h in hits:
            problems.append(f"{where}: positioners {ia[h]} and {ib[h]} collide "
                            f"(distance {dmin[h]:.3f} mm < {need[h]:.3f} mm)")
            if len(incidents) < MAX_PROBLEMS:
                incidents.append({"step": k, "positioners": [int(ia[h]), int(ib[h])], "t": float(tmin[h]),
                                  "distance": float(dmin[h]), "required": float(need[h])})
    valid = not problems
    return _result(valid, collisions, at_target, problems, len(confs) - 1, clearance, incidents, (undecided, depth))


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


def _ids(idx: Any, limit: int = 10) -> str:
    idx = [int(i) for i in idx]
    text = ", ".join(map(str, idx[:limit]))
    return text + (f", ... ({len(idx)} in all)" if len(idx) > limit else "")


def _result(valid: bool, collisions: int, at_target: int, problems: list[str], steps: int,
            clearance: float | None, incidents: list[dict[str, Any]] | None = None,
            undecided: tuple[int, float] = (0, 0.0)) -> dict[str, Any]:
    if len(problems) > MAX_PROBLEMS:
        problems = problems[:MAX_PROBLEMS] + [f"... and {len(problems) - MAX_PROBLEMS} more"]
    if clearance is not None and not math.isfinite(clearance):
        clearance = None
    return {"valid": bool(valid), "collisions": int(collisions), "at_target": int(at_target), "problems": problems,
            "steps": int(steps), "min_clearance": clearance, "incidents": list(incidents or []),
            "undecided": int(undecided[0]), "undecided_depth": float(undecided[1])}
