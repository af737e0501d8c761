"""Small problems that have no complete plan, for the partial-plan tests and benchmark.

:func:`tight_case` draws, from a seed alone, a problem of 3 to 6 rotary robots packed on a
triangular grid tighter than any instrument (pitch 15 to 19 mm, 15 mm arms, 2 mm buffers),
with a collision-free start and target drawn at random, until the independent oracle
(:func:`~.oracle.api.oracle_solve`) finds no single-move plan for it.  So every case is one
where a partial plan is the answer, and small enough for the oracle's exhaustive search over
subsets (:mod:`.oracle.subsets`): 12 positions per robot up to 3 robots, then 10, 8 and 6
(at most 50,000 configurations).
"""

from __future__ import annotations

import random
from typing import Any, Iterator

from ..errors import InputError
from ..problems.problem import parse_problem
from .oracle import OracleUndecided, oracle_solve

__all__ = ["tight_case", "tight_cases"]

#: the six neighbours of a triangular-grid point, in axial coordinates
_AXIAL = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)]


def _cluster(rng: random.Random, n: int) -> list[tuple[int, int]]:
    """``n`` connected points of the triangular grid, grown from the origin at random."""
    points = [(0, 0)]
    while len(points) < n:
        a, b = rng.choice(points)
        da, db = rng.choice(_AXIAL)
        if (a + da, b + db) not in points:
            points.append((a + da, b + db))
    return points


#: positions per robot by number of robots
_STEPS = {3: 12, 4: 10, 5: 8, 6: 6}


def _draw(rng: random.Random, sizes: tuple[int, ...]) -> dict[str, Any]:
    n = rng.choice(sizes)
    pitch = round(rng.uniform(15.0, 19.0), 1)
    steps = _STEPS[n]
    xy = [[round(pitch * (a + b / 2), 4), round(pitch * b * 0.8660254037844386, 4)] for a, b in _cluster(rng, n)]
    return {"layout": {"kind": "points", "xy": xy}, "kinematics": {"kind": "rotary", "arm": 15.0, "steps": steps},
            "collision": {"buffer": 2.0},
            "start": [rng.randrange(steps) for _ in range(n)], "target": [rng.randrange(steps) for _ in range(n)]}


def tight_case(seed: int, sizes: tuple[int, ...] = (3, 4, 5, 6), tries: int = 2000) -> dict[str, Any] | None:
    """A PROBLEM.json object of one of ``sizes`` robots (3 to 6) with no complete single-move
    plan (module docstring), or None when ``tries`` draws give none; the same ``seed`` and
    ``sizes`` give the same problem."""
    rng = random.Random(seed)
    for _ in range(tries):
        data = _draw(rng, sizes)
        try:
            parse_problem(data)
            if oracle_solve(data) is None:
                return data
        except (InputError, OracleUndecided):
            continue  # a colliding start or target, or ties the oracle cannot decide: draw again
    return None


def tight_cases(count: int, first_seed: int = 0,
                sizes: tuple[int, ...] = (3, 4, 5, 6)) -> Iterator[tuple[int, dict[str, Any]]]:
    """``count`` cases ``(seed, problem)`` from consecutive seeds, each as soon as it is drawn
    (a seed with none is skipped)."""
    found, seed = 0, first_seed
    while found < count:
        case = tight_case(seed, sizes)
        if case is not None:
            found += 1
            yield seed, case
        seed += 1
