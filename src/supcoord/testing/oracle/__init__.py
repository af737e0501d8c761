"""An independent geometric oracle for the planner's tests (not part of the top-level API).

Everything the planner's answers rest on is written again here, on purpose, from
``docs/formats.md`` alone: the hex layout, the kinematics (complex numbers), the
segment distance (the origin against a Minkowski difference, :mod:`.distance`), the
true reach (elbow included), a **certified** swept check (branch and bound on ``t``
with a Lipschitz bound, three-valued: free, collides, undecided to 10⁻⁹ mm —
:mod:`.certified_sweep`), three-valued pair tables (:mod:`.tables`) and a breadth-first search
over joint configurations (:mod:`.bfs`) for the single-move and the simultaneous
semantics.  It imports none of :mod:`supcoord.geometry`, :mod:`supcoord.planning`,
:mod:`supcoord.problems` — only numpy and :mod:`supcoord.errors` — so that "the planner
agrees with the oracle" checks the geometry, not a model against its own encoding.

Input: a problem's JSON (``Problem.to_json()``, or as written: starts and targets as
indices, ``alpha_beta_deg`` or ``xy_mm``; ``alpha_range``; ``collision.margin``); each
robot then moves on its own lattice holding its exact start and target angles
(:func:`.oracle_model.exact_lattice`); entry points in :mod:`.api`.

>>> p = {"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
...      "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
...      "collision": {"buffer": 2.0}, "start": [6, 0], "target": [0, 9]}
>>> oracle_solve(p), oracle_moves(p)[:4]      # b turns up out of the way first, then a turns to b
(9, [(1, 0, -1), (1, 0, -1), (1, 0, -1), (0, 0, 1)])
>>> oracle_reachable(p), oracle_optimal_makespan(p)
(133, 6)
"""

from .api import (
    oracle_bases,
    oracle_bounds,
    oracle_check_moves,
    oracle_check_steps,
    oracle_ends_deg,
    oracle_lattices_deg,
    oracle_motion,
    oracle_moves,
    oracle_optimal_makespan,
    oracle_reach,
    oracle_reachable,
    oracle_solve,
)
from .bfs import MAX_CONFIGURATIONS, OracleUndecided
from .oracle_model import OracleInputError
from .certified_sweep import FREE, HIT, UNDECIDED

__all__ = [
    "FREE",
    "HIT",
    "MAX_CONFIGURATIONS",
    "UNDECIDED",
    "OracleInputError",
    "OracleUndecided",
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
