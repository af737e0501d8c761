"""The same problem on a finer lattice.

A lattice is part of the model, not of the instrument: where the problem's lattice has
only a certificate of the *single-move* model (one joint turning at a time between its
positions), a finer one may hold a plan, as on SDSS-V's APO wok, where four robots that
cannot pass each other on 30° steps fold on 20° steps.  :func:`finer_steps` gives the
next lattice (steps two-thirds as long) and :func:`at_lattice` re-derives the problem on
it from its own file: the same instrument, robots, buffers, obstacles and offline
robots, and the start and target at their exact angles (each robot's lattice holds them,
``docs/formats.md``, exactness).  The re-derivation is a function of the problem file and
the numbers of positions only, so ``supcoord check`` validates a plan made on a finer
lattice (its ``lattice`` field) on the very problem the planner solved.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from ..geometry.kinematics import MAX_POSITIONS
from .problem import Problem, parse_problem

__all__ = ["finer_steps", "at_lattice"]


def finer_steps(problem: Problem, steps: Sequence[int] | None = None) -> tuple[int, int] | None:
    """The alpha-beta lattice with steps two-thirds as long as ``problem``'s (alpha ``A``
    positions → ``⌈1.5·A⌉`` where it wraps, ``⌈1.5·(A−1)⌉ + 1`` between hard stops; beta
    likewise between its stops): 13 × 7 → 19 × 10; or as long as those of the lattice
    ``steps`` of the same joints (19 × 10 → 28 × 15 on the SDSS-V woks).  None: not an alpha-beta problem, or the
    finer lattice would exceed the tables' bound (:data:`MAX_POSITIONS`)."""
    kin = problem.kinematics
    if kin.kind != "alpha-beta":
        return None
    alpha, beta = kin.joints
    n_alpha, n_beta = (alpha.steps, beta.steps) if steps is None else (int(steps[0]), int(steps[1]))
    a = math.ceil(1.5 * n_alpha) if alpha.wraps else math.ceil(1.5 * (n_alpha - 1)) + 1
    b = math.ceil(1.5 * (n_beta - 1)) + 1
    return None if a * b > MAX_POSITIONS else (a, b)


def at_lattice(problem: Problem, steps: Sequence[Any]) -> Problem:
    """``problem`` with ``alpha_steps, beta_steps = steps``: its file (:meth:`Problem.to_json`)
    with the start and target written as their joint angles, parsed again.  Raises
    :class:`InputError` (naming ``lattice``) for steps that are not an alpha-beta lattice
    within the bounds of ``docs/formats.md``."""
    kin = problem.kinematics
    if kin.kind != "alpha-beta":
        raise InputError(f"lattice: a {kin.kind} problem has no alpha-beta lattice to change", value=list(steps),
                         where="lattice")
    if len(steps) != 2 or not all(isinstance(s, (int, np.integer)) and not isinstance(s, bool) for s in steps):
        raise InputError(f"lattice must be [alpha_steps, beta_steps], got {list(steps)!r}", value=list(steps),
                         where="lattice")
    data = problem.to_json()
    data["kinematics"] = dict(data["kinematics"], alpha_steps=int(steps[0]), beta_steps=int(steps[1]))
    for name, conf in (("start", problem.start), ("target", problem.target)):
        if not isinstance(data[name], dict):  # indices of the uniform lattice: their angles
            ang = problem.angles_deg(conf)
            if kin.joints[0].wraps:
                ang[..., 0] %= 360.0
            data[name] = {"alpha_beta_deg": ang.tolist()}
    try:
        return parse_problem(data, problem.where)
    except InputError as exc:
        raise InputError(f"lattice {list(steps)}: {exc.message}", value=list(steps), where="lattice") from None
