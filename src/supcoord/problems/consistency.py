"""Consistency checks of a :class:`Problem` and a :class:`Plan` at the library's boundary.

A ``Problem`` is validated when it is parsed, and it is immutable: assigning a field raises
and its arrays (``bases``, ``buffers``, ``start``, ``target``) are read-only.  But a user may
build one with ``Problem(...)`` or :func:`dataclasses.replace` whose ``target`` is a float
array, a list or ``None``, or whose ``kinematics`` is ``None``; :func:`check_problem`, called
where a public function takes a problem (``solve``, ``validate_plan``, ``plan_from_moves``,
the figures), catches such a field before it reaches the planner, where it could raise a
raw ``IndexError`` or loop forever.  :func:`plan_defects` lists what is malformed in a
``Plan`` (fields of the wrong type, configurations that are not integer arrays of the
problem's shape), for ``validate_plan`` to report instead of raising, and
:func:`check_plan` raises them for the functions that draw a plan.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from ..errors import InputError
from ..geometry.joint_space import Kinematics
from ..geometry.layout import _short

from .problem import Problem

__all__ = ["check_problem", "plan_defects", "check_plan"]


def _is_int(v: Any) -> bool:
    return isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_))


def _finite_array(value: Any, shape: tuple[int | None, ...], name: str, where: str) -> np.ndarray:
    if not isinstance(value, np.ndarray) or value.dtype.kind not in "fiu" or value.ndim != len(shape) or any(
            s is not None and s != t for s, t in zip(shape, value.shape)):
        want = " × ".join("M" if s is None else str(s) for s in shape)
        raise InputError(f"{where}.{name} must be a ({want}) numeric array, got {_short(value)}", value=name)
    if not np.all(np.isfinite(value)):
        raise InputError(f"{where}.{name} holds a number that is not finite", value=name)
    return value


def check_problem(problem: Any, where: str = "problem") -> None:
    """Raise :class:`InputError` unless ``problem`` is a :class:`Problem` whose fields are
    still consistent with each other (module docstring); ``where`` names the parameter."""
    if not isinstance(problem, Problem):
        raise InputError(f"{where}: needs a Problem (supcoord.load_problem, random_problem, preset_problem), got "
                         f"{type(problem).__name__}", value=type(problem).__name__)
    n, steps = _check_robots(problem, where)
    _check_positions(problem, n, steps, where)
    _check_surroundings(problem, n, where)


def _check_robots(problem: Problem, where: str) -> tuple[int, list[int]]:
    """Kinematics, bases, per-robot kinematics and buffers; the robots and the joints' steps."""
    kin = problem.kinematics
    if not isinstance(kin, Kinematics):
        raise InputError(f"{where}.kinematics must be a Kinematics, got {_short(kin)}", value=kin)
    bases = _finite_array(problem.bases, (None, 2), "bases", where)
    n, steps = len(bases), [j.steps for j in kin.joints]
    robots = problem.robot_kinematics
    if robots is not None and (not isinstance(robots, list) or len(robots) != n or not all(
            isinstance(k, Kinematics) and [j.steps for j in k.joints] == steps for k in robots)):
        raise InputError(f"{where}.robot_kinematics must be None or a list of {n} kinematics with the joints of "
                         f"{where}.kinematics", value=None)
    buffers = _finite_array(problem.buffers, (n,), "buffers", where)
    if np.any(buffers < 0):
        raise InputError(f"{where}.buffers holds a negative buffer", value=None)
    return n, steps


def _check_positions(problem: Problem, n: int, steps: list[int], where: str) -> None:
    """Start and target on the lattice, one priority per robot."""
    for name in ("start", "target"):
        q = getattr(problem, name)
        if not isinstance(q, np.ndarray) or q.dtype.kind not in "iu" or q.shape != (n, len(steps)):
            raise InputError(f"{where}.{name} must be an integer array of shape ({n}, {len(steps)}) (positions on "
                             f"the lattice), got {_short(q)}", value=name)
        if np.any(q < 0) or np.any(q >= np.array(steps)):
            raise InputError(f"{where}.{name} holds a position outside the lattice {' × '.join(map(str, steps))}",
                             value=name)
    if not isinstance(problem.priority, list) or len(problem.priority) != n or not all(
            _is_int(v) for v in problem.priority):
        raise InputError(f"{where}.priority must be a list of {n} integers, got {_short(problem.priority)}",
                         value=problem.priority)


def _check_surroundings(problem: Problem, n: int, where: str) -> None:
    """Obstacles and their buffers, margins, the layout, robots held and under joint rules."""
    obstacles = _finite_array(problem.obstacles, (None, 2, 2), "obstacles", where)
    _finite_array(problem.obstacle_buffers, (len(obstacles),), "obstacle_buffers", where)
    for name in ("margin", "obstacle_margin"):
        v = getattr(problem, name)
        if not (v is None and name == "obstacle_margin") and not (
                isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)):
            raise InputError(f"{where}.{name} must be a finite number, got {_short(v)}", value=v)
    if not isinstance(problem.layout, dict):
        raise InputError(f"{where}.layout must be a dict, got {_short(problem.layout)}", value=None)
    for name in ("held", "joint_rules"):
        table = getattr(problem, name)
        if not isinstance(table, dict) or not all(_is_int(p) and 0 <= p < n for p in table):
            raise InputError(f"{where}.{name} must be a dict keyed by robot index, got {_short(table)}",
                             value=None)


#: Plan fields and the types they hold (None allowed where listed)
_PLAN_FIELDS: dict[str, tuple[type, ...]] = {
    "status": (str,), "configurations": (list, tuple), "makespan": (numbers.Integral, type(None)),
    "lower_bound": (numbers.Integral, type(None)), "events": (list, tuple), "reason": (str,), "stats": (dict,),
    "angles_deg": (list, tuple), "trajectories": (list, type(None)), "motion_time_s": (numbers.Real, type(None)),
    "lattice": (tuple, list, type(None)),
}


def plan_defects(plan: Any, n: int | None = None, joints: int | None = None) -> list[str]:
    """What is malformed in ``plan`` (empty: nothing): a field of the wrong type, a
    configuration that is not an integer ``(n, joints)`` array, an angle array of another
    shape or a ``lattice`` that is not a tuple of integers.  ``n``/``joints``: the problem's
    (None: not compared).  ``plan`` is a :class:`~supcoord.problems.plan.Plan` (callers check)."""
    out = []
    for name, types in _PLAN_FIELDS.items():
        v = getattr(plan, name, None)
        if not isinstance(v, types) or isinstance(v, bool):
            out.append(f"plan.{name} must be {' or '.join(t.__name__ for t in types)}, got {_short(v)}")
    if out:
        return out
    if plan.lattice is not None and not all(_is_int(s) and 2 <= s <= 10**6 for s in plan.lattice):
        out.append(f"plan.lattice must be a tuple of joint sizes, got {_short(plan.lattice)}")
    shape = None if n is None or joints is None else (n, joints)
    for name, kinds in (("configurations", "iu"), ("angles_deg", "fiu")):
        for k, c in enumerate(getattr(plan, name)):
            defect = _array_defect(f"plan.{name}[{k}]", c, kinds, shape)
            if defect is not None:
                out.append(defect)
                break
    return out


def _array_defect(name: str, value: Any, kinds: str, shape: tuple[int, int] | None) -> str | None:
    """What is wrong with one configuration (``kinds`` ``"iu"``: integer positions, integral
    floats accepted) or pose (``"fiu"``: numbers) of a plan, or None."""
    try:
        a = np.asarray(value)
    except (ValueError, TypeError, OverflowError) as exc:
        return f"{name} is not an array ({type(exc).__name__})"
    integral = a.dtype.kind in "iu" or (a.dtype.kind == "f" and a.size and np.all(np.isfinite(a))
                                        and np.all(a == np.round(a)) and np.all(np.abs(a) < 2**62))
    if (kinds == "iu" and not integral) or (kinds != "iu" and a.dtype.kind not in kinds):
        return f"{name} must hold {'integer positions' if kinds == 'iu' else 'numbers'}, got {_short(value)}"
    if shape is not None and a.shape != shape:
        return (f"{name} has shape {list(a.shape)}, not {list(shape)} ({shape[0]} positioners, {shape[1]} joints): "
                f"a plan for another problem?")
    return None


def check_plan(plan: Any, problem: Any, where: str = "plan") -> None:
    """Raise :class:`InputError` naming the first of :func:`plan_defects` (``problem``'s shape)."""
    defects = plan_defects(plan, problem.n, problem.kinematics.n_joints)
    if defects:
        raise InputError(defects[0], value=None)
