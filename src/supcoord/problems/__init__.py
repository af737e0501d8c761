"""Geometric coordination problems and plans: PROBLEM.json, PLAN.json, random problems, the validator.

A :class:`Problem` is a layout, a kinematics, a buffer, start and target configurations
and priorities (``docs/formats.md``); a :class:`Plan` is a sequence of configurations.
:func:`validate_plan` replays a plan with its own geometry (it shares no code with the
planner's collision tables) and is the referee of every plan supcoord returns.
:func:`jaeger_paths` writes a plan as SDSS-V's robot controller jaeger runs it, and
:func:`check_jaeger` checks such a trajectory, whoever wrote it, exactly as written.
"""

from .jaeger import JaegerPaths, jaeger_paths, write_jaeger
from .plan import Plan, compact_moves, event_name, load_plan, lower_bound, parse_event, parse_plan, plan_from_moves
from .presets import preset_problem
from .problem import Problem, load_problem, parse_problem
from .random import random_configuration, random_problem
from .validate import ValidationResult, validate_plan
from .validate_jaeger import JaegerCheck, check_jaeger, read_jaeger

__all__ = [
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
    "ValidationResult",
    "random_configuration",
    "random_problem",
    "preset_problem",
    "JaegerPaths",
    "jaeger_paths",
    "write_jaeger",
    "JaegerCheck",
    "check_jaeger",
    "read_jaeger",
]
