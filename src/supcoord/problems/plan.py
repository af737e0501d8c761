"""PLAN.json ↔ :class:`Plan`; lower bounds; greedy compaction of single moves.

A plan is a sequence of configurations ``c_0 = start, …, c_T = target`` in which every
joint of every positioner moves at most one step between consecutive configurations
(``docs/formats.md``); ``makespan = T``.  The supervisor's events move one joint of one
positioner by one step: event names are ``v{p}``/``w{p}`` (rotary: index ``+1`` =
clockwise / ``−1``), ``va{p}``/``wa{p}`` and ``vb{p}``/``wb{p}`` (alpha-beta: alpha/beta
index ``+1``/``−1``), ``p`` counting positioners from 0.

- Lower bound: ``LB = max_p max_j d_j(start_p, target_p)`` with ``d_j`` the cyclic
  distance where joint ``j`` wraps (``|Δ|`` otherwise) — no plan can be shorter, since a
  joint moves at most one step per configuration.
- Compaction (:func:`compact_moves`): a valid sequence of single moves ``m_1 … m_K`` is
  merged greedily into simultaneous steps: ``m_k`` joins the current step if its joint
  has not moved in that step yet and the merged motion (all joints of the step moving
  together, linearly in joint space) is collision-free for every neighbour pair with a
  moving member (:func:`~supcoord.geometry.collision.motion_collides`); otherwise it starts a new step.
  The last configuration of each step is one of the sequence's own configurations.

A plan also carries the joint angles of its configurations (``angles_deg``) and, given a
joint speed, timed ``trajectories`` and ``motion_time_s`` (:mod:`.trajectory`: the timing
model); a plan may consist of those alone (made by another tool), which the validator
checks as well.
"""

from __future__ import annotations

import copy
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from ..errors import FormatError, InputError
from ..outputs import atomic_write_text
from ..progress import summary_html, summary_repr
from ..geometry.collision import DEFAULT_TOL, robots_motion_collides
from ..geometry.kinematics import MAX_POSITIONS, Kinematics, _is_int
from ..geometry.layout import _short
from .off_target import OffTarget, off_target_to_json, parse_off_target
from .problem import Problem, read_json
from .trajectory import check_speed, motion_to_json, parse_motion_fields, wrapped_angles, with_motion

__all__ = ["MAX_PLAN_BYTES", "MAX_PLAN_POSITIONS", "Plan", "Move", "lower_bound", "event_name", "parse_event", "checked_step", "apply_moves", "reversed_moves", "exchanged",
           "compact_moves", "plan_from_moves", "load_plan", "parse_plan", "STATUSES"]

STATUSES = ("complete", "infeasible", "unknown", "partial")
#: largest PLAN.json read (bytes) and most positions in it (configurations × positioners)
MAX_PLAN_BYTES = 256 * 2**20
MAX_PLAN_POSITIONS = 20_000_000
#: ``(positioner, joint, delta)``: one joint of one positioner moves one step
Move = tuple[int, int, int]
_PREFIX = {"rotary": [("v", "w")], "alpha-beta": [("va", "wa"), ("vb", "wb")]}


def event_name(kin: Kinematics, p: int, joint: int, delta: int) -> str:
    """The event of a single move: ``event_name(Rotary(..), 3, 0, +1) == 'v3'``."""
    fwd, bwd = _PREFIX[kin.kind][joint]
    return f"{fwd if delta > 0 else bwd}{int(p)}"


def parse_event(kin: Kinematics, name: str) -> Move:
    """Inverse of :func:`event_name`; raises :class:`InputError` for an unknown event."""
    m = re.fullmatch(r"([a-z]+)(\d+)", str(name))
    if m:
        for joint, (fwd, bwd) in enumerate(_PREFIX[kin.kind]):
            if m.group(1) in (fwd, bwd):
                return int(m.group(2)), joint, (+1 if m.group(1) == fwd else -1)
    raise InputError(f"unknown move event {name!r} for {kin.kind} kinematics", value=name)


def lower_bound(problem: Problem) -> int:
    """Largest single-joint distance from start to target (cyclic where the joint wraps)."""
    if problem.n == 0:
        return 0
    return int(problem.kinematics.joint_distance(problem.start, problem.target).max())


@dataclass
class Plan:
    """The PLAN.json object; ``configurations`` is a list of ``(N, J)`` int arrays, ``angles_deg``
    of ``(N, J)`` float arrays; a plan may hold angles or trajectories without configurations."""

    status: str
    configurations: list[np.ndarray] = field(default_factory=list)
    makespan: int | None = None
    lower_bound: int | None = None
    events: list[str] = field(default_factory=list)
    reason: str = ""
    stats: dict = field(default_factory=dict)
    #: joint angles (degrees) of each configuration, ``(N, J)`` float arrays (or the plan itself)
    angles_deg: list[np.ndarray] = field(default_factory=list)
    #: per robot ``{joint name: (K, 2) array of [t_s, deg]}`` (:mod:`.trajectory`), or None
    trajectories: list[dict] | None = None
    motion_time_s: float | None = None
    #: the joints' numbers of positions the configurations index where ``solve`` planned on a
    #: finer lattice than the problem's (:mod:`.refine`); None: the problem's own
    lattice: tuple[int, ...] | None = None
    #: a ``partial`` plan's robots off target (:mod:`.off_target`); empty for the other statuses
    off_target: tuple[OffTarget, ...] = ()
    #: a ``partial`` plan: how many robots end at their targets, whether that is proven the most
    #: (the least total weight off target) the discretised model allows, and the most that could
    #: be on target (an upper bound; equal to ``on_target`` where ``optimal``); None otherwise
    on_target: int | None = None
    optimal: bool | None = None
    on_target_bound: int | None = None

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise InputError(f"plan status must be one of {STATUSES}, got {self.status!r}", value=self.status)
        if self.makespan is None and self.configurations:
            self.makespan = len(self.configurations) - 1

    def summary(self) -> dict[str, Any]:
        """What a notebook shows of the plan (its ``repr`` and HTML): status, positioners,
        steps, lower bound, motion time, moves, the reason of a verdict; never the arrays."""
        out: dict[str, Any] = {"status": self.status}
        try:
            if self.configurations:
                out["positioners"] = len(self.configurations[0])
            for key, value in (("makespan", self.makespan), ("lower_bound", self.lower_bound),
                               ("motion_time_s", None if self.motion_time_s is None else round(float(self.motion_time_s), 3)),
                               ("single_moves", len(self.events) or None), ("lattice", self.lattice),
                               ("seconds", round(float(self.stats["seconds"]), 2) if "seconds" in (self.stats or {})
                                else None),
                               ("reason", self.reason or None)):
                if value is not None:
                    out[key] = value
        except Exception:  # noqa: BLE001 - a repr shows what it can of a broken object
            out["invalid"] = True
        return out

    def __repr__(self) -> str:
        return summary_repr("Plan", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("Plan", self.summary())

    def to_json(self, kin: Kinematics | Problem) -> dict:
        """The PLAN.json object; given the :class:`Problem` (not only its kinematics), the
        ``angles_deg`` of the configurations are written even when the plan holds none."""
        problem = kin if isinstance(kin, Problem) else None
        kin = problem.kinematics if problem is not None else kin
        out = {
            "status": self.status,
            "configurations": [[kin.position_to_json(q) for q in c] for c in self.configurations],
            "makespan": self.makespan,
            "lower_bound": self.lower_bound,
            "events": list(self.events),
            "reason": self.reason,
            "stats": dict(self.stats),
        }
        angles = self.angles_deg
        if not angles and problem is not None and self.configurations and self.lattice is None:
            angles = wrapped_angles(problem, self.configurations)
        if angles or problem is not None:
            out["angles_deg"] = [np.asarray(a, float).tolist() for a in angles]
        out.update(motion_to_json(self))
        if self.lattice is not None:
            out["lattice"] = [int(s) for s in self.lattice]
        if self.status == "partial":
            out.update(off_target=off_target_to_json(self.off_target), on_target=self.on_target,
                       optimal=self.optimal, on_target_bound=self.on_target_bound)
        if problem is not None:  # the collision definition the plan was made and checked under
            out["collision"] = problem.collision_statement()
        return out

    def dump(self, path: str | Path, kin: Kinematics | Problem) -> None:
        """Write PLAN.json atomically (:func:`supcoord.outputs.atomic_write_text`)."""
        atomic_write_text(path, json.dumps(self.to_json(kin)) + "\n")


def load_plan(path: str | Path, problem: Problem) -> Plan:
    """Read a PLAN.json file for ``problem`` (structure checked; geometry left to the
    validator); at most :data:`MAX_PLAN_BYTES` and :data:`MAX_PLAN_POSITIONS` positions."""
    return parse_plan(read_json(path, "plan", MAX_PLAN_BYTES), problem, str(path))


def parse_plan(data: Any, problem: Problem, where: str | None = None) -> Plan:
    """Validate the structure of a PLAN.json object: types and shapes, not ranges or geometry.

    Out-of-range positions, jumps and collisions are properties of the plan that the
    validator reports; a malformed file (wrong types, wrong number of positioners) is
    a :class:`FormatError`.
    """
    if not isinstance(data, dict):
        raise FormatError(f"a plan must be a JSON object, got {_short(data)}", value=data, where=where)
    status = data.get("status")
    if status not in STATUSES:
        raise FormatError(f"plan status must be one of {list(STATUSES)}, got {_short(status)}", value=status, where=where)
    out = _configurations(data.get("configurations", []), problem, where)
    ints = {}
    for key in ("makespan", "lower_bound"):
        v = data.get(key)
        if v is not None and not _is_int(v):
            raise FormatError(f"{key} must be an integer or null, got {_short(v)}", value=v, where=where)
        ints[key] = v
    events = data.get("events", [])
    if not isinstance(events, list) or not all(isinstance(e, str) for e in events):
        raise FormatError(f"events must be a list of strings, got {_short(events)}", value=events, where=where)
    reason = data.get("reason", "")
    if not isinstance(reason, str):
        raise FormatError(f"reason must be a string, got {_short(reason)}", value=reason, where=where)
    stats = data.get("stats", {})
    if not isinstance(stats, dict):
        raise FormatError(f"stats must be an object, got {_short(stats)}", value=stats, where=where)
    angles, trajectories, motion = parse_motion_fields(data, problem, len(out), MAX_PLAN_POSITIONS, where)
    lattice = data.get("lattice")
    n_joints = problem.kinematics.n_joints
    if lattice is not None and not (isinstance(lattice, list) and len(lattice) == n_joints
                                    and all(_is_int(s) and 2 <= s <= MAX_POSITIONS for s in lattice)):
        raise FormatError(f"lattice must list {n_joints} numbers of positions in [2, {MAX_POSITIONS}], got "
                          f"{_short(lattice)}", value=lattice, where=where)
    plan = Plan(status, out, ints["makespan"], ints["lower_bound"], events, reason, stats, angles, trajectories,
                motion, None if lattice is None else tuple(int(s) for s in lattice))
    if status == "partial" or data.get("off_target"):
        _partial_fields(plan, data, problem.n, where)
    return plan


def _partial_fields(plan: Plan, data: dict, n: int, where: str | None) -> None:
    """A partial plan's ``off_target`` (at least one robot), ``on_target``, ``optimal`` and
    ``on_target_bound``, checked and set on ``plan``; refused on a plan of another status."""
    if plan.status != "partial":
        raise FormatError(f"off_target is only for a partial plan, not a {plan.status} one", value=plan.status,
                          where=where)
    plan.off_target = parse_off_target(data.get("off_target"), n, where)
    if not plan.off_target:
        raise FormatError("a partial plan must list its robots off target (off_target is empty)", value=None,
                          where=where)
    on, bound, optimal = data.get("on_target"), data.get("on_target_bound"), data.get("optimal")
    if on is not None and not (_is_int(on) and 0 <= on <= n):
        raise FormatError(f"on_target must be an integer in [0, {n}] or null, got {_short(on)}", value=on, where=where)
    if bound is not None and not (_is_int(bound) and (on or 0) <= bound <= n):
        raise FormatError(f"on_target_bound must be an integer in [on_target, {n}] or null, got {_short(bound)}",
                          value=bound, where=where)
    if optimal is not None and not isinstance(optimal, bool):
        raise FormatError(f"optimal must be true, false or null, got {_short(optimal)}", value=optimal, where=where)
    plan.on_target = None if on is None else int(on)
    plan.on_target_bound = None if bound is None else int(bound)
    plan.optimal = optimal


def _configurations(confs: Any, problem: Problem, where: str | None) -> list[np.ndarray]:
    """PLAN.json's ``configurations``: lists of ``problem.n`` positions (an index per joint;
    a rotary one a plain integer), as ``(N, J)`` int arrays."""
    if not isinstance(confs, list):
        raise FormatError(f"configurations must be a list, got {_short(confs)}", value=confs, where=where)
    kin, n = problem.kinematics, problem.n
    if len(confs) * n > MAX_PLAN_POSITIONS:
        raise InputError(f"configurations: {len(confs)} configurations of {n} positioners are more than the "
                         f"{MAX_PLAN_POSITIONS} positions a plan may have", value=len(confs), where=where)
    out = []
    for t, c in enumerate(confs):
        if not isinstance(c, list) or len(c) != n:
            got = f"{len(c)} positions" if isinstance(c, list) else _short(c)
            raise FormatError(f"configurations[{t}] must list {n} positions, got {got}", value=c, where=where)
        rows = []
        for i, v in enumerate(c):
            q = [v] if kin.kind == "rotary" else v
            if (not isinstance(q, list) or len(q) != kin.n_joints or not all(_is_int(x) for x in q)
                    or not all(abs(x) < 2**62 for x in q)):
                raise FormatError(f"configurations[{t}][{i}] must be a {kin.kind} position, got {_short(v)}",
                                  value=v, where=where)
            rows.append(q)
        out.append(np.array(rows, dtype=np.int64).reshape(n, kin.n_joints))
    return out


def checked_step(kin: Kinematics, q: Any, k: int, move: Move) -> np.ndarray:
    """``kin.step(q, joint, delta)`` for move number ``k`` ``(p, joint, delta)`` of a sequence;
    :class:`InputError` if it drives positioner ``p`` past a hard stop."""
    p, joint, delta = move
    nxt = kin.step(q, joint, delta)
    if nxt is None:
        raise InputError(f"move {k} ({event_name(kin, p, joint, delta)}) drives positioner {p} past a hard stop",
                         value=(p, joint, delta))
    return nxt


def reversed_moves(moves: Sequence[Move]) -> list[Move]:
    """The moves backwards, each undone: a single-move sequence target → start where
    ``moves`` go start → target (the planner's guards are symmetric, :mod:`supcoord.planning.guards`)."""
    return [(p, j, -d) for p, j, d in reversed(moves)]


def exchanged(problem: Problem) -> Problem:
    """``problem`` with start and target exchanged (the same tables and guards)."""
    back = copy.copy(problem)  # shares the tables and every cache: none depends on start or target
    back.__dict__.update(start=problem.target, target=problem.start)  # a Problem refuses assignment
    return back


def apply_moves(problem: Problem, moves: Iterable[Move]) -> list[np.ndarray]:
    """Configurations visited by a sequence of single moves from ``start`` (one per move)."""
    kin = problem.kinematics
    c = problem.start.copy()
    out = [c.copy()]
    for k, (p, joint, delta) in enumerate(moves):
        _check_move(problem, k, p, joint, delta)
        c[p] = checked_step(kin, c[p], k, (p, joint, delta))
        out.append(c.copy())
    return out


def compact_moves(problem: Problem, moves: Sequence[Move], tol: float = DEFAULT_TOL) -> list[np.ndarray]:
    """Greedily merge single moves into simultaneous collision-free steps (module docstring)."""
    kin = problem.kinematics
    pairs = problem.pairs
    bsum = problem.buffers[pairs[:, 0]] + problem.buffers[pairs[:, 1]]
    involving: dict[int, np.ndarray] = {}
    for k, (a, b) in enumerate(pairs):
        involving.setdefault(int(a), []).append(k)  # type: ignore[attr-defined]
        involving.setdefault(int(b), []).append(k)  # type: ignore[attr-defined]
    involving = {p: np.array(ks, dtype=int) for p, ks in involving.items()}
    c = problem.start.copy()
    delta = np.zeros_like(c)
    out = [c.copy()]
    for k, (p, joint, d) in enumerate(moves):
        _check_move(problem, k, p, joint, d)
        checked_step(kin, c[p] + delta[p], k, (p, joint, d))
        trial = delta.copy()
        trial[p, joint] += d
        if delta[p, joint] != 0 or _step_collides(problem, c, trial, involving.get(p, np.zeros(0, int)), bsum, tol):
            c = kin.wrap(c + delta)  # close the current step
            out.append(c.copy())
            delta = np.zeros_like(c)
            delta[p, joint] = d
        else:
            delta = trial
    if np.any(delta):
        out.append(kin.wrap(c + delta))
    return out


def plan_from_moves(problem: Problem, moves: Sequence[Move], *, compact: bool = True,
                    stats: dict | None = None, speed: float | None = None) -> Plan:
    """A ``complete`` plan from a single-move sequence that reaches the target, with its
    ``angles_deg`` and, given a joint ``speed`` (degrees per second), its trajectories."""
    from .consistency import check_problem

    check_problem(problem)
    if not isinstance(moves, (list, tuple)):
        raise InputError(f"moves must be a list of (positioner, joint, ±1), got {type(moves).__name__}", value=None,
                         where="moves")
    check_speed(speed)
    kin = problem.kinematics
    confs = compact_moves(problem, moves) if compact else apply_moves(problem, moves)
    if not np.array_equal(confs[-1], problem.target):
        raise InputError("the moves do not end at the target configuration", value=len(moves))
    events = [event_name(kin, p, j, d) for p, j, d in moves]
    plan = Plan("complete", confs, len(confs) - 1, lower_bound(problem), events, "", dict(stats or {}))
    return with_motion(plan, problem, speed)


def _check_move(problem: Problem, k: int, p: Any, joint: Any, d: Any) -> None:
    if not (_is_int(p) and 0 <= p < problem.n and _is_int(joint) and 0 <= joint < problem.kinematics.n_joints
            and d in (1, -1)):
        raise InputError(f"move {k} must be (positioner, joint, ±1), got {(p, joint, d)!r}", value=(p, joint, d))


def _step_collides(problem: Problem, c: np.ndarray, delta: np.ndarray, ks: np.ndarray, bsum: np.ndarray,
                   tol: float) -> bool:
    """Does the simultaneous motion ``c → c + delta`` collide for one of the pairs ``ks``?"""
    if len(ks) == 0:
        return False
    bases = problem.bases
    a, b = problem.pairs[ks, 0], problem.pairs[ks, 1]
    hit = robots_motion_collides(problem.kins, a, bases[a], c[a], delta[a], b, bases[b], c[b], delta[b], bsum[ks], tol)
    return bool(hit.any())
