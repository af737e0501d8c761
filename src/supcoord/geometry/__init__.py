"""Focal-plane geometry: layouts of bases, kinematics of one positioner, collision tables, instruments.

Nothing here knows about problems, plans or BDDs: a layout is an ``(N, 2)`` array of
bases in mm, a kinematics maps a discrete position to arm segments (and steps between
positions), :mod:`.segments` measures distances between segments, and :mod:`.collision`
turns these into static and swept collision tables.  See
``docs/geometry.md`` for the conventions (angles, ordering, collision, swept checks).
"""

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
from .presets_table import PRESETS, Preset, folded_position, preset_kinematics
from .kinematics import AlphaBeta, Joint, Kinematics, Rotary, kinematics_from_spec
from .layout import hex_count, hex_grid, layout_from_spec, points_layout

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
    "PRESETS",
    "Preset",
    "folded_position",
    "preset_kinematics",
]
