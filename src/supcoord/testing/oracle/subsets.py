"""The oracle's answer to "how many robots can reach their targets": an exhaustive search over subsets.

For a problem (``Problem.to_json()``) of a few robots, every set ``O`` of robots is tried,
fewest first: ``O`` off target means each of its robots ends at its start instead of its
target (PROBLEM.json's ``target`` rewritten), every other robot at its target, and ``O``
*works* when the oracle's own breadth-first search (:func:`.api.oracle_solve`, single moves)
finds a plan from the start to that end.  An end where two robots collide has no plan.  The
fewest robots of a working ``O`` give the most robots on target, which is what a partial
plan's ``optimal`` claims.

This module shares no code with the planner: it reads the problem as JSON and uses only the
oracle's search (:mod:`.bfs`, :mod:`.tables`).

>>> p = {"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [9, 15]]},
...      "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
...      "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]}
>>> best = oracle_most_on_target(p)
>>> best.on_target, best.fewest_off, oracle_group_unsolvable(p, [0, 1, 2])
(2, [(0,)], True)
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .api import oracle_solve
from .bfs import Space
from .oracle_model import OracleInputError, OracleProblem

__all__ = ["MostOnTarget", "oracle_most_on_target", "oracle_most_on_target_anywhere", "oracle_group_unsolvable",
           "ends_at_start"]


@dataclass(frozen=True)
class MostOnTarget:
    """The oracle's answer: ``on_target`` (the most robots that can end at their targets) and
    ``fewest_off`` (every set of that many robots off target that works, sorted)."""

    on_target: int
    fewest_off: list[tuple[int, ...]]


def ends_at_start(problem_json: dict, off: Sequence[int]) -> dict:
    """``problem_json`` with each robot of ``off`` ending at its start (``target`` rewritten;
    starts and targets as index lists)."""
    out = copy.deepcopy(problem_json)
    for r in off:
        out["target"][int(r)] = copy.deepcopy(out["start"][int(r)])
    return out


def _works(problem_json: dict, off: Sequence[int], members: Sequence[int] | None = None) -> bool:
    try:
        return oracle_solve(ends_at_start(problem_json, off), members) is not None
    except OracleInputError as exc:  # an end where two robots collide has no plan
        if "configuration collides" in str(exc):
            return False
        raise


def oracle_most_on_target(problem_json: Any) -> MostOnTarget:
    """Every set of robots off target, fewest first, until some work (module docstring).

    Raises :class:`~.bfs.OracleUndecided` where an answer rests on an undecided swept entry.
    """
    n = len(problem_json["start"])
    moving = [r for r in range(n) if problem_json["start"][r] != problem_json["target"][r]]
    for k in range(len(moving) + 1):
        found = [off for off in itertools.combinations(moving, k) if _works(problem_json, off)]
        if found:
            return MostOnTarget(n - k, found)
    raise AssertionError("every robot at its start is a plan")  # pragma: no cover - the start is free


def oracle_group_unsolvable(problem_json: Any, members: Sequence[int], at_start: Sequence[int] = ()) -> bool:
    """Is a certificate right: can the robots ``members`` alone (every other robot removed),
    those of ``at_start`` ending at their starts, not all reach their ends?"""
    return not _works(problem_json, list(at_start), list(members))


def oracle_most_on_target_anywhere(problem_json: Any) -> int:
    """The most robots at their targets in any configuration reachable from the start by single
    moves: robots off target end anywhere they can be brought (parked), not only at their starts.

    One breadth-first search to exhaustion (:meth:`.bfs.Space.single`, ``goal=False``) over
    every robot, then the largest count of robots at their targets among the configurations it
    reached.  No partial plan can have more robots on target; where the planner parks no robot,
    :func:`oracle_most_on_target` is at most this.

    Raises :class:`~.bfs.OracleUndecided` where the reachable set rests on an undecided swept entry.

    >>> p = {"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [9, 15]]},
    ...      "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...      "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]}
    >>> oracle_most_on_target_anywhere(p)
    2
    """
    space = Space(OracleProblem.from_json(problem_json))
    outcome = space.single(goal=False)
    assert outcome.seen is not None
    digits = space.digits(outcome.seen)
    target = [int(space.prob.target[p]) for p in space.members]
    return int(np.max(np.sum(digits == np.asarray(target)[None, :], axis=1)))
