"""Joint lattices: the positions' angles of one joint, uniform or holding exact angles.

A joint with ``n`` positions has angles ``g_0 < … < g_{n−1}`` (degrees); between
neighbouring positions it turns linearly.  :func:`exact_lattice` builds a robot's own
lattice from the uniform one so that it holds the robot's start and target angles exactly
(``docs/formats.md``, extensions for real instruments).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError
from .layout import _finite_number, _short

__all__ = ["exact_lattice", "interpolate", "joint_range", "angle_table", "points"]


def exact_lattice(uniform: Any, values: Any, wraps: bool) -> tuple[np.ndarray, list[int]]:
    """A joint's lattice holding the angles ``values`` exactly: ``(table, slots)``.

    Each value replaces the uniform position nearest to it (``uniform``: the joint's
    positions in degrees, evenly spaced; a wrapping joint's run over one turn); two values
    nearest to the same position take it and the neighbour that keeps steps shortest, so the
    table stays strictly increasing and every step is at most 2 uniform steps.  ``slots[k]`` is
    the position of ``values[k]``.  Equal values share a slot.

    >>> table, slots = exact_lattice([0.0, 90.0, 180.0, 270.0], [100.0, 80.0], wraps=True)
    >>> table.tolist(), slots
    ([0.0, 80.0, 100.0, 270.0], [2, 1])
    """
    grid = np.asarray(uniform, dtype=float)
    n = len(grid)
    h = float(grid[1] - grid[0])
    table = grid.copy()
    distinct = sorted(set(float(v) for v in values))
    wanted: dict[float, int] = {}
    for v in distinct:
        i = int(round((v - grid[0]) / h))
        wanted[v] = i % n if wraps else min(max(i, 0), n - 1)
    def offset(v: float, i: int) -> float:  # signed distance from the uniform position i
        d = v - grid[i]
        return (d + 180.0) % 360.0 - 180.0 if wraps else d

    taken: dict[int, float] = {}
    for v in distinct:
        i = wanted[v]
        if i in taken:  # two values nearest to one position: one of them takes a neighbour
            low, high = sorted((taken.pop(i), v), key=lambda x: offset(x, i))
            up, down = (i + 1) % n if wraps else i + 1, (i - 1) % n if wraps else i - 1
            # the side whose next step stays shorter: up leaves 2h − off(high), down 2h + off(low)
            go_up = (offset(high, i) + offset(low, i) >= 0 or down < 0) and up < n and up not in taken
            if go_up or down < 0 or down in taken:
                taken[i], taken[up] = low, high
                wanted[low], wanted[high] = i, up
            else:
                taken[down], taken[i] = low, high
                wanted[low], wanted[high] = down, i
            continue
        taken[i] = v
    for i, v in taken.items():
        if wraps:  # the representative of v nearest to the uniform position
            v = v + 360.0 * round((grid[i] - v) / 360.0)
        table[i] = v
    steps = np.diff(table)
    if wraps:
        steps = np.append(steps, table[0] + 360.0 - table[-1])
    if not np.all(steps > 0):
        raise InputError(f"angles {distinct} cannot be placed in a lattice of {n} positions: use more steps",
                         value=distinct)
    return table, [wanted[float(v)] for v in values]


def interpolate(x: np.ndarray, table: np.ndarray, wraps: bool) -> np.ndarray:
    """Piecewise-linear angle of fractional positions ``x`` over a lattice (degrees); a wrapping
    joint continues over ``[−1, n]`` (one step either way past the ends)."""
    n = len(table)
    if not wraps:
        return np.interp(x, np.arange(n), table)
    xp = np.arange(-1, n + 1)
    fp = np.concatenate([[table[-1] - 360.0], table, [table[0] + 360.0]])
    return np.interp(x, xp, fp)


def joint_range(value: Any, name: str) -> tuple[float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 2 or not all(_finite_number(v) for v in value):
        raise InputError(f"kinematics.{name} must be [lo, hi] in degrees, got {_short(value)}", value=value)
    lo, hi = float(value[0]), float(value[1])
    if not (-360.0 <= lo < hi <= 360.0 and hi - lo <= 360.0):
        raise InputError(f"kinematics.{name} must satisfy -360 <= lo < hi <= 360 and hi - lo <= 360, got {[lo, hi]}",
                         value=value)
    return lo, hi


def angle_table(value: Any, joint: str, steps: int, rng: tuple[float, float] | None, wraps: bool) -> np.ndarray:
    table = np.asarray(value, dtype=float)
    if table.shape != (steps,) or not np.all(np.isfinite(table)):
        raise InputError(f"{joint} lattice must be {steps} finite angles (degrees), got {_short(value)}", value=value)
    steps_deg = np.diff(table)
    if wraps:
        steps_deg = np.append(steps_deg, table[0] + 360.0 - table[-1])
    if not np.all(steps_deg > 0):
        raise InputError(f"{joint} lattice angles must increase strictly (within one turn), got {_short(value)}",
                         value=value)
    if rng is not None and (table[0] < rng[0] - 1e-9 or table[-1] > rng[1] + 1e-9):
        raise InputError(f"{joint} lattice angles must lie in {list(rng)}, got {_short(value)}", value=value)
    table.setflags(write=False)
    return table


def points(value: Any, name: str, count: int) -> np.ndarray:
    pts = np.asarray(value, dtype=float)
    if pts.shape != (count, 2) or not np.all(np.isfinite(pts)) or np.abs(pts).max() > 1e6:
        raise InputError(f"kinematics.{name} must be {count} point(s) [x, y] in mm, got {_short(value)}", value=value)
    pts.setflags(write=False)
    return pts
