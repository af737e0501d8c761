"""Explicit-state checks for tests and benchmarks (not part of the top-level API).

- :mod:`supcoord.testing.oracle` — the **independent geometric oracle**: its own layout,
  kinematics, segment distance, certified swept checks and breadth-first search over
  joint configurations, importing none of the planner, the problems or the geometry.
  Verdicts, ranks, certificates and optimal makespans are checked against it.
- :mod:`supcoord.testing.explicit_search` — explicit twins of the planner's *encoding*
  (:func:`bfs_plan_naive`, :func:`reachable_naive`, :func:`blockers_naive`,
  :func:`optimal_makespan_naive`): the same guards as the symbolic model, searched one
  configuration at a time, so they check the BDDs against the guards, not the geometry.
"""

from .explicit_search import (
    bfs_plan_naive,
    blockers_naive,
    optimal_makespan_naive,
    reachable_naive,
)
from .oracle import (
    oracle_bounds,
    oracle_moves,
    oracle_optimal_makespan,
    oracle_reachable,
    oracle_solve,
)

__all__ = ["bfs_plan_naive", "blockers_naive", "optimal_makespan_naive", "oracle_bounds", "oracle_moves",
           "oracle_optimal_makespan", "oracle_reachable", "oracle_solve", "reachable_naive"]
