"""The oracle's entry points: PROBLEM.json (``Problem.to_json()``) in, exact answers out.

- :func:`oracle_solve` — the length of a shortest single-move plan start → target, or
  ``None`` when none exists; ``members`` solves the sub-problem of those positioners
  with every other one *removed* (how an infeasibility certificate is re-checked).
- :func:`oracle_bounds` — the same with ties (undecided entries) free and blocked: the
  true answer lies between.
- :func:`oracle_moves` — one shortest plan as ``(positioner, joint, ±1)`` moves.
- :func:`oracle_reachable` — how many configurations the single moves reach from the start.
- :func:`oracle_optimal_makespan` — the fewest simultaneous steps (every joint −1/0/+1).
- :func:`oracle_check_moves` / :func:`oracle_check_steps` — a given plan (single moves, or a
  schedule of configurations under the simultaneous semantics) replayed on the oracle's
  tables: ``None`` when every step is certified free and it runs start → target.
- :func:`oracle_lattices_deg` / :func:`oracle_ends_deg` — each robot's own lattice and
  its exact start and target angles (degrees), as the oracle builds them from the angles,
  fibre positions or indices of the problem.
- :func:`oracle_motion` — one motion of two positioners, three-valued
  (:data:`FREE`, :data:`HIT`, :data:`UNDECIDED`).

Each raises :class:`OracleUndecided` when its answer depends on a swept entry it could
not decide, and :class:`OracleInputError` (an :class:`~supcoord.errors.InputError`) for
a problem it cannot take: a colliding start or target, a search over more than
:data:`.bfs.MAX_CONFIGURATIONS` configurations.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .bfs import Space
from .distance import segment_gap
from .oracle_model import Arm, OracleProblem
from .tables import PairTables

__all__ = [
    "oracle_bases",
    "oracle_bounds",
    "oracle_check_moves",
    "oracle_check_steps",
    "oracle_ends_deg",
    "oracle_lattices_deg",
    "oracle_motion",
    "oracle_moves",
    "oracle_optimal_makespan",
    "oracle_reach",
    "oracle_reachable",
    "oracle_solve",
]


def _space(problem_json: Any, members: Sequence[int] | None) -> Space:
    return Space(OracleProblem.from_json(problem_json), None if members is None else list(members))


def oracle_solve(problem_json: Any, members: Sequence[int] | None = None) -> int | None:
    """Shortest number of single moves start → target of ``members`` (default: all), or ``None``."""
    return _space(problem_json, members).single().distance


def oracle_bounds(problem_json: Any, members: Sequence[int] | None = None) -> tuple[int | None, int | None]:
    """``(lo, hi)``: the shortest single-move distance with the undecided swept entries
    (ties) free, and with them blocked (``None``: no plan).  Whatever those entries are,
    the true distance lies in ``[lo, hi]`` (``None`` counting as infinite); they are equal
    when the ties do not matter, and then :func:`oracle_solve` returns that value."""
    loose, strict = _space(problem_json, members).single_bounds()
    return loose.distance, strict.distance


def oracle_moves(problem_json: Any, members: Sequence[int] | None = None) -> list[tuple[int, int, int]] | None:
    """A shortest single-move plan as ``(positioner, joint, delta)`` moves, or ``None``."""
    return _space(problem_json, members).single(path=True).moves


def oracle_reachable(problem_json: Any, members: Sequence[int] | None = None) -> int:
    """Number of configurations of ``members`` reachable from the start by single moves."""
    return _space(problem_json, members).single(goal=False).reachable


def oracle_optimal_makespan(problem_json: Any, members: Sequence[int] | None = None) -> int | None:
    """Fewest simultaneous steps start → target (every joint of every member −1/0/+1 per step)."""
    return _space(problem_json, members).simultaneous().distance


def oracle_motion(problem_json: Any, a: int, qa: Sequence[int], da: Sequence[int], b: int, qb: Sequence[int],
                  db: Sequence[int]) -> int:
    """Does positioner ``a`` moving ``qa → qa + da`` while ``b`` moves ``qb → qb + db``
    (joint indices of each one's own lattice, linear in joint space) collide?  ``FREE`` (0), ``HIT`` (1) or
    ``UNDECIDED`` (2)."""
    prob = OracleProblem.from_json(problem_json)
    arm_a, arm_b = prob.arm_of(a), prob.arm_of(b)
    t = PairTables(arm_a, complex(prob.bases[b] - prob.bases[a]), prob.need(a, b), arm_b)
    rows = [np.asarray(v, dtype=np.int64).reshape(1, -1) for v in (qa, da, qb, db)]
    o = t.offset
    ends = []
    for s in (0.0, 1.0):
        a0, a1 = arm_a.segment(rows[0] + s * rows[1])
        b0, b1 = arm_b.segment(rows[2] + s * rows[3])
        ends.append(segment_gap(a0, a1, o + b0, o + b1))
    return int(t.motion(rows[0], rows[1], rows[2], rows[3], ends[0], ends[1])[0])


def oracle_reach(kinematics_json: Any) -> float:
    """The true reach of an arm: the farthest any point of its colliding segment gets from the base."""
    return Arm.from_json(kinematics_json).reach


def oracle_bases(problem_json: Any) -> np.ndarray:
    """The bases as the oracle rebuilds them, ``(N, 2)`` floats."""
    b = OracleProblem.from_json(problem_json).bases
    return np.stack([b.real, b.imag], axis=-1)


def oracle_lattices_deg(problem_json: Any) -> list[tuple[np.ndarray, ...]]:
    """Per robot, per joint the angles (degrees) of its positions: its own lattice where
    the problem gives angles or fibre positions, else the uniform one."""
    prob = OracleProblem.from_json(problem_json)
    out = []
    for p in range(prob.n):
        arm = prob.arm_of(p)
        joints = []
        for j, s in enumerate(arm.steps):
            table = None if arm.tables is None else arm.tables[j]
            joints.append(np.degrees(arm.zero[j] + arm.per_step[j] * np.arange(s)) if table is None
                          else np.array(table, dtype=float))
        out.append(tuple(joints))
    return out


def oracle_ends_deg(problem_json: Any) -> tuple[np.ndarray, np.ndarray]:
    """``(start, target)``: each robot's joint angles (degrees, ``(N, J)``) at its start
    and target position, read off its own lattice."""
    prob = OracleProblem.from_json(problem_json)
    lat = oracle_lattices_deg(problem_json)
    out = []
    for conf in (prob.start, prob.target):
        rows = []
        for p, i in enumerate(conf):
            q = np.unravel_index(i, prob.arm.steps)
            rows.append([float(lat[p][j][q[j]]) for j in range(prob.arm.n_joints)])
        out.append(np.array(rows))
    return out[0], out[1]


def oracle_check_moves(problem_json: Any, moves: Sequence[tuple[int, int, int]],
                       members: Sequence[int] | None = None) -> int | None:
    """Single moves ``(positioner, joint, ±1)`` replayed from the start: ``None`` if each is
    certified free and they end at the target, else the index of the first bad one
    (``len(moves)``: they end elsewhere)."""
    space = Space(OracleProblem.from_json(problem_json), members, replay_only=True)
    return space.check_moves([tuple(int(v) for v in m) for m in moves])


def oracle_check_steps(problem_json: Any, configurations: Sequence[Any]) -> int | None:
    """A schedule of configurations (``(N, J)`` joint indices) under the simultaneous
    semantics: ``None`` if it runs start → target with every step certified free, else the
    index ``k`` of the first bad step ``k → k + 1`` (``len``: wrong ends)."""
    return Space(OracleProblem.from_json(problem_json), None, replay_only=True).check_steps(list(configurations))
