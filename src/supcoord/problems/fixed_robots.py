"""Robots kept fixed: PROBLEM.json's ``"fixed"`` and ``supcoord solve --keep``.

A robot kept fixed stays at its start angles from the first configuration to the last, as
an obstacle for the others.  It is the same thing as an offline robot (``"offline"``), and
it is held by the same machinery (:attr:`~supcoord.problems.problem.Problem.held`: its
unary tables refuse every move, the validator refuses a plan that moves it); the difference
is only where its angles come from: an offline robot's are given, a fixed robot's are its
``start``.  Its ``target`` is replaced by its start.

A robot whose motors were disabled in the middle of a field is offline at the angles where
it stopped: give them as ``"offline": {"robot": [α, β]}`` (or make them its start and list
it in ``"fixed"``).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable

from ..errors import InputError
from ..geometry.layout import _short
from .problem import Problem

__all__ = ["keep_fixed", "parse_robot_list"]


def parse_robot_list(text: str, n: int, where: str) -> list[int]:
    """``"3,17"`` (a command-line list of robot indices) as sorted indices; an
    :class:`InputError` naming ``where`` for anything else.

    >>> parse_robot_list("3, 1", 7, "--keep")
    [1, 3]
    """
    out: set[int] = set()
    for part in str(text).split(","):
        part = part.strip()
        if not part.isascii() or not part.isdigit() or len(part) > 18 or int(part) >= n:
            raise InputError(f"{_short(part)} is not a robot index in [0, {n - 1}]", value=part, where=where)
        out.add(int(part))
    return sorted(out)


def keep_fixed(problem: Problem, robots: Iterable[int], where: str = "keep") -> Problem:
    """``problem`` with ``robots`` kept at their start angles, as obstacles for the others.

    Parameters
    ----------
    problem : Problem
        The problem (any kinematics; lengths in mm).
    robots : iterable of int
        Robot indices (from 0) to keep where they start.
    where : str, default "keep"
        What an error names (the command line passes ``"--keep"``).

    Returns
    -------
    Problem
        A copy whose :attr:`~Problem.held` holds the robots at their start positions and
        whose target puts them there; its collision tables are built afresh (they fold in
        the robots held).

    Raises
    ------
    InputError
        A robot index out of range, or a robot kept at its start that collides with a
        neighbour's target.

    Examples
    --------
    >>> from supcoord.problems import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [40, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 8.0, "steps": 4},
    ...                    "collision": {"buffer": 1.0}, "start": [0, 0], "target": [1, 2]})
    >>> kept = keep_fixed(p, [1])
    >>> sorted(kept.held), kept.target[:, 0].tolist()
    ([1], [1, 0])

    References
    ----------
    ``docs/formats.md`` (PROBLEM.json ``fixed``, ``offline``).
    """
    robots = sorted({int(p) for p in robots})
    bad = [p for p in robots if not 0 <= p < problem.n]
    if bad:
        raise InputError(f"{bad[0]} is not a robot index in [0, {problem.n - 1}]", value=bad[0], where=where)
    if not robots:
        return problem
    target = problem.target.copy()
    target[robots] = problem.start[robots]
    held = dict(problem.held)
    held.update({p: tuple(int(v) for v in problem.start[p]) for p in robots})
    out = dataclasses.replace(problem, target=target, held=held, _tables=None, _unary=None)
    for a, b, d in out.collisions(out.target):
        kept = a if a in robots else b if b in robots else None
        if kept is not None:
            other = b if kept == a else a
            raise InputError(f"robot {kept} kept at its start collides with robot {other} at its target "
                             f"({d:.3f} mm apart)", value=[kept, other], where=where)
    return out
