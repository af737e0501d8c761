"""Focal-plane layouts: where the positioners' bases are (mm, focal-plane x/y).

A hexagonal grid of ``R`` rings and pitch ``p`` is the lattice
``{p·(a + b/2, b·√3/2) : a, b ∈ ℤ}`` cut to the hexagon of hex-distance ``≤ R``::

    H(R, p) = {0} ∪ ⋃_{r=1..R} ring(r),   |ring(r)| = 6r,   |H(R, p)| = 1 + 3R(R+1)

ordered as ``docs/formats.md`` fixes it: the centre first, then ring by ring; each ring
starts at its corner on the +x axis, ``(r·p, 0)``, and walks counter-clockwise
along the hexagon's six edges (corner ``k`` at ``r·p·(cos 60°k, sin 60°k)``, ``r − 1``
points between consecutive corners).  Along one straight edge the polar angle
grows monotonically, so this is also "sorted by polar angle in [0, 2π) within the
ring".

A ``points`` layout is an explicit list ``[[x, y], ...]`` in mm, kept in the order
given.

How many robots a layout may have is set by the memory there is
(:mod:`.layout_limits`), checked from ``rings`` or the list's length before any array is made.

References
----------
- J. Sayres et al., SDSS-V focal plane system (robots on a 22.4 mm hexagonal grid).
- DESI Collaboration, The DESI Experiment Part II (10.4 mm pitch hexagonal petals).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from .layout_limits import check_robot_count

__all__ = ["hex_count", "hex_grid", "hex_rings_of", "points_layout", "layout_from_spec"]


def hex_count(rings: int) -> int:
    """Number of positioners in a hex grid of ``rings`` rings: ``1 + 3R(R+1)``.

    >>> [hex_count(r) for r in range(4)]
    [1, 7, 19, 37]
    """
    if isinstance(rings, bool) or not isinstance(rings, (int, np.integer)) or rings < 0:
        raise InputError(f"rings must be a non-negative integer, got {rings!r}", value=rings)
    return 1 + 3 * int(rings) * (int(rings) + 1)


def hex_grid(rings: int, pitch: float) -> np.ndarray:
    """Bases of a hex grid as an ``(1 + 3R(R+1), 2)`` float array, in ``docs/formats.md`` order.

    >>> hex_grid(1, 2.0).round(3).tolist()[:3]
    [[0.0, 0.0], [2.0, 0.0], [1.0, 1.732]]
    """
    n = hex_count(rings)
    if not _positive_number(pitch):
        raise InputError(f"pitch must be a positive number of mm, got {pitch!r}", value=pitch)
    corners = np.array([[math.cos(math.pi / 3 * k), math.sin(math.pi / 3 * k)] for k in range(7)])
    out = [np.zeros((1, 2))]
    for r in range(1, int(rings) + 1):
        # corner k to corner k+1 in r equal steps, corner k included, corner k+1 not
        t = np.arange(r)[:, None] / r
        edges = [r * ((1 - t) * corners[k] + t * corners[k + 1]) for k in range(6)]
        out.append(np.concatenate(edges))
    xy = np.concatenate(out) * float(pitch)
    if len(xy) != n:  # an invariant, kept as a project exception (never a bare assert)
        raise InputError(f"hex grid produced {len(xy)} points, expected {n}", value=rings)
    return xy


def hex_rings_of(n: int) -> int | None:
    """The ``R`` with ``1 + 3R(R+1) = n``, or ``None`` when ``n`` is not a hex count.

    >>> hex_rings_of(19), hex_rings_of(20)
    (2, None)
    """
    r = 0
    while hex_count(r) < n:
        r += 1
    return r if hex_count(r) == n else None


def points_layout(xy: Any, where: str | None = None) -> np.ndarray:
    """An explicit list of bases ``[[x, y], ...]`` (mm) as an ``(N, 2)`` array; distinct points."""
    if not isinstance(xy, (list, tuple, np.ndarray)) or len(xy) == 0:
        raise FormatError(f"layout.xy must be a non-empty list of [x, y] pairs, got {_short(xy)}", value=xy, where=where)
    check_robot_count(len(xy), "layout.xy", f"{len(xy)} points", where)
    rows = []
    for i, p in enumerate(xy):
        if (not isinstance(p, (list, tuple, np.ndarray)) or len(p) != 2
                or not all(_finite_number(v) and abs(v) <= 1e9 for v in p)):
            raise FormatError(f"layout.xy[{i}] must be a pair of finite numbers [x, y] (mm, |x|, |y| <= 1e9), got {_short(p)}",
                              value=p, where=where)
        rows.append([float(p[0]), float(p[1])])
    arr = np.array(rows, dtype=float)
    _, first = np.unique(arr, axis=0, return_index=True)
    if len(first) != len(arr):
        dup = sorted(set(range(len(arr))) - set(first.tolist()))[0]
        raise InputError(f"layout.xy[{dup}] = {rows[dup]} repeats an earlier base", value=rows[dup], where=where)
    return arr


def layout_from_spec(spec: Any, where: str | None = None) -> np.ndarray:
    """The bases described by a PROBLEM.json ``layout`` object (``hex`` or ``points``)."""
    if not isinstance(spec, dict):
        raise FormatError(f"layout must be an object, got {_short(spec)}", value=spec, where=where)
    kind = spec.get("kind")
    if kind == "hex":
        rings, pitch = spec.get("rings"), spec.get("pitch")
        if isinstance(rings, bool) or not isinstance(rings, int) or rings < 0:
            raise FormatError(f"layout.rings must be a non-negative integer, got {_short(rings)}", value=rings,
                              where=where)
        check_robot_count(hex_count(rings), "layout.rings", rings, where)
        if not _positive_number(pitch) or pitch > 1e6:
            raise FormatError(f"layout.pitch must be a positive number (mm) <= 1e6, got {_short(pitch)}", value=pitch, where=where)
        return hex_grid(rings, float(pitch))
    if kind == "points":
        return points_layout(spec.get("xy"), where=where)
    raise FormatError(f"layout.kind must be 'hex' or 'points', got {_short(kind)}", value=kind, where=where)


def _finite_number(v: Any) -> bool:
    if not isinstance(v, (int, float, np.integer, np.floating)) or isinstance(v, bool):
        return False
    try:
        return math.isfinite(v)
    except OverflowError:  # an int too large for a float
        return False


def _positive_number(v: Any) -> bool:
    return _finite_number(v) and v > 0


def _short(v: Any, limit: int = 60) -> str:
    text = repr(v)
    return text if len(text) <= limit else text[: limit - 3] + "..."
