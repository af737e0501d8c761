"""The domain: focal-plane layouts, kinematics, collision tables, problems, plans, validation.

See ``docs/geometry.md`` for the conventions (angles, ordering, collision, swept checks).
"""

from .layout import hex_count, hex_grid, layout_from_spec, points_layout
from .kinematics import AlphaBeta, Joint, Kinematics, Rotary, kinematics_from_spec
from .collision import (
    CollisionTables,
    colliding_pairs,
    motion_collides,
    neighbour_pairs,
    segment_distance,
    simultaneous_table,
    static_table,
    swept_table,
)
from .problem import Problem, load_problem, parse_problem
from .plan import Plan, compact_moves, event_name, load_plan, lower_bound, parse_event, parse_plan, plan_from_moves
from .validate import validate_plan
from .random_problems import random_configuration, random_problem
from .presets import PRESETS, Preset, preset_problem
from .coordination import CoordinationModel, conflict_components, rcm_order
from .planner import solve
from .search_naive import bfs_plan_naive, optimal_makespan_naive

__all__ = [
    "hex_count",
    "hex_grid",
    "layout_from_spec",
    "points_layout",
    "AlphaBeta",
    "Joint",
    "Kinematics",
    "Rotary",
    "kinematics_from_spec",
    "CollisionTables",
    "colliding_pairs",
    "motion_collides",
    "neighbour_pairs",
    "segment_distance",
    "simultaneous_table",
    "static_table",
    "swept_table",
    "Problem",
    "load_problem",
    "parse_problem",
    "Plan",
    "compact_moves",
    "event_name",
    "load_plan",
    "lower_bound",
    "parse_event",
    "parse_plan",
    "plan_from_moves",
    "validate_plan",
    "random_configuration",
    "random_problem",
    "PRESETS",
    "Preset",
    "preset_problem",
    "CoordinationModel",
    "conflict_components",
    "rcm_order",
    "solve",
    "bfs_plan_naive",
    "optimal_makespan_naive",
]
