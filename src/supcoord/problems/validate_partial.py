"""What the validator checks a ``partial`` plan against: the problem it solves completely
(each robot listed in ``off_target`` ending where the entry says), and the robots at their
own targets at its end (formats.md, "Partial plans")."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .off_target import OffTarget, folded_ends, partial_end
from .plan import Plan
from .problem import Problem

__all__ = ["partial_problem", "at_whole_target"]


def partial_problem(problem: Problem, plan: Plan, problems: list[str]) -> Problem:
    """The problem a ``partial`` plan solves completely: ``problem`` with each robot listed in
    ``off_target`` ending at its start, folded, or parked at its ``at`` where its entry says
    (:func:`~.off_target.partial_end`, :func:`~.off_target.folded_ends`); a list that names
    no robot, or one robot twice, or a parked position outside the robot's lattice, is a problem
    of the plan."""
    entries = plan.off_target
    robots = [e.robot for e in entries if isinstance(e, OffTarget)]
    if (len(robots) != len(entries) or not robots or len(set(robots)) != len(robots)
            or not all(isinstance(r, (int, np.integer)) and 0 <= r < problem.n for r in robots)):
        problems.append(f"a partial plan must list each robot off target once, by index in [0, {problem.n}), "
                        f"got {len(entries)} entries")
        return problem
    for e in entries:
        kin = problem.kin(e.robot)
        if e.end == "parked" and (e.at is None or len(e.at) != kin.n_joints or not kin.in_range(np.array(e.at))):
            problems.append(f"robot {e.robot} is parked at {e.at}: not a position of its lattice {kin.shape}")
            return problem
    return replace(problem, target=partial_end(problem.start, problem.target, tuple(entries), folded_ends(problem)))


def at_whole_target(whole: Problem, ends: Problem, confs: list[np.ndarray], at_ends: int) -> int:
    """The robots at their own targets at the end of a partial plan that ended ``at_ends``
    robots where ``ends`` says (exact for configurations; for angles, of a plan that ends
    where it says)."""
    if confs:
        return int(np.sum(np.all(confs[-1] == whole.target, axis=1)))
    moved = np.any(ends.target != whole.target, axis=1)
    return int(at_ends - np.sum(moved))
