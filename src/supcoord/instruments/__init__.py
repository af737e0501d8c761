"""Real instruments: SDSS-V's measured focal planes (``sdss-v-apo``, ``sdss-v-lco``) as kaiju models them.

:func:`load_instrument` reads the packaged SDSS-V FPS calibrations (``sdss/fps_calibrations``,
release 2025.12.04) and returns an :class:`InstrumentGeometry`: 500 robots (bases, measured
arms, fibres, offsets), 60 fiducials and 6 guide cameras as obstacles, and kaiju's collision
segment, buffers, joint ranges and folded lattice, each number with its source.
:func:`robot_forward` and :func:`fibre_xy` are kaiju's forward kinematics.
:mod:`.wok` writes wok problems: :func:`folded_configuration`, :func:`random_wok_targets`
(kaiju-like, seeded, decollided), :func:`wok_targets` (by positioner ID, in wok mm or angles)
and :func:`wok_problem` (a PROBLEM.json object); :mod:`.hard_fields` makes hard fields
(:func:`hard_wok_field`: offline robots in the way, crowded targets, provably unreachable
targets). See ``docs/instruments.md``.
"""

from .acceptance import CollisionDefinition, MotionLimits, collision_definition, motion_limits
from .sdss_v import (
    INSTRUMENTS,
    InstrumentGeometry,
    fibre_joints,
    fibre_xy,
    load_instrument,
    robot_collision_distance,
    robot_forward,
)
from .hard_fields import HardField, UnreachableCertificate, hard_wok_field, unreachable_certificate
from .wok import folded_configuration, random_wok_targets, wok_problem, wok_targets

__all__ = [
    "INSTRUMENTS",
    "InstrumentGeometry",
    "load_instrument",
    "robot_forward",
    "fibre_xy",
    "fibre_joints",
    "robot_collision_distance",
    "folded_configuration",
    "random_wok_targets",
    "wok_targets",
    "wok_problem",
    "hard_wok_field",
    "HardField",
    "UnreachableCertificate",
    "unreachable_certificate",
    "CollisionDefinition",
    "MotionLimits",
    "collision_definition",
    "motion_limits",
]
