"""Starts and targets given as joint angles or fibre positions: each robot's own lattice.

Written again from ``docs/formats.md`` (extensions for real instruments), sharing no code
with :mod:`supcoord.problems` or :mod:`supcoord.geometry`:

- ``{"alpha_beta_deg": [[α, β], ...]}``: a wrapping alpha is taken mod 360 into [0, 360);
  angles outside the joint ranges are refused;
- ``{"xy_mm": [[x, y], ...], "handedness": "right" | "left" | "any"}``: the fibre (the beta
  arm's tip) at ``(x, y)``, by inverse kinematics (:func:`fibre_inverse`): ``right`` is the
  solution with ``β`` in [0°, 180°], ``left`` the other, ``any`` the first of them inside
  the ranges (each shifted by whole turns into its range);
- a list of indices: the uniform positions ``g_i`` (:func:`uniform_deg`).

Every robot then gets its own lattice per joint (:func:`exact_lattice`) holding its start
and target angles exactly; its start and target are those slots
(:meth:`.oracle_model.OracleProblem.from_json`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .refusal import OracleInputError

__all__ = ["HANDEDNESS", "exact_lattice", "fibre_inverse", "side_angles", "uniform_deg"]

HANDEDNESS = ("right", "left", "any")


def uniform_deg(steps: int, wraps: bool, lo: float, hi: float) -> np.ndarray:
    """A joint's uniform positions in degrees: ``360·i/n`` wrapping, else ``lo + (hi − lo)·i/(n − 1)``."""
    if wraps:
        return 360.0 * np.arange(steps) / steps
    return lo + (hi - lo) * np.arange(steps) / (steps - 1)


def exact_lattice(grid: Sequence[float], values: Sequence[float], wraps: bool) -> tuple[np.ndarray, list[int]]:
    """One joint's own lattice (degrees) holding ``values`` exactly, and each value's slot.

    From the uniform positions ``g_0 < … < g_{n−1}`` (spacing ``h``) each distinct value
    ``v`` takes the slot ``round((v − g_0)/h)`` (mod ``n`` wrapping, else clipped).  Two
    values in one slot ``i``: ordered by their offsets ``off(v) = v − g_i`` (wrapped into
    [−180, 180) for a wrapping joint) as ``low``, ``high``; ``high`` moves up to ``i + 1``
    when ``off(high) + off(low) ≥ 0`` (or ``i − 1`` does not exist) and ``i + 1`` exists,
    else ``low`` moves down to ``i − 1``.  A slot's angle becomes its value (wrapping: the
    representative ``v + 360k`` nearest to ``g_i``).  The table must increase strictly
    (wrapping: within one turn), else :class:`OracleInputError`.

    >>> exact_lattice([0.0, 90.0, 180.0, 270.0], [100.0, 80.0], True)[1]
    [2, 1]
    """
    g = [float(x) for x in grid]
    n = len(g)
    h = g[1] - g[0]

    def slot_of(v: float) -> int:
        i = round((v - g[0]) / h)
        return i % n if wraps else min(max(i, 0), n - 1)

    def off(v: float, i: int) -> float:
        d = v - g[i]
        return (d + 180.0) % 360.0 - 180.0 if wraps else d

    def exists(i: int) -> bool:
        return wraps or 0 <= i < n

    vals = []
    for v in values:
        if float(v) not in vals:
            vals.append(float(v))
    slots = {v: slot_of(v) for v in vals}
    if len(vals) == 2 and slots[vals[0]] == slots[vals[1]]:
        i = slots[vals[0]]
        low, high = sorted(vals, key=lambda v: off(v, i))
        up, down = i + 1, i - 1
        if (off(high, i) + off(low, i) >= 0 or not exists(down)) and exists(up):
            slots[high] = up % n
        else:
            slots[low] = down % n
    table = np.array(g, dtype=float)
    for v, i in slots.items():
        table[i] = v + 360.0 * round((g[i] - v) / 360.0) if wraps else v
    steps = np.diff(table)
    if wraps:
        steps = np.append(steps, table[0] + 360.0 - table[-1])
    if not np.all(steps > 0):
        raise OracleInputError(f"angles {vals} do not fit a lattice of {n} positions", value=vals)
    return table, [slots[float(v)] for v in values]


def fibre_inverse(a: float, b: float, z: complex) -> list[tuple[float, float]]:
    """Both elbow solutions ``(α, β)`` (degrees) putting the fibre (the beta arm's tip) at
    ``z`` relative to the base: ``|z|² = a² + b² + 2ab·cos β``; the ``right`` one
    (``β ∈ [0°, 180°]``) first, then ``left`` (``β ∈ (−180°, 0°]``, 180° when folded flat);
    ``α = arg z − arg(a + b·e^{iβ})`` in [0, 360).  Empty when ``z`` is out of reach (within
    10⁻⁹ mm of the annulus' edge counts as on it)."""
    c = (abs(z) ** 2 - a * a - b * b) / (2 * a * b)
    if abs(c) > 1 + 1e-9 * (abs(z) + a + b) / (a * b):
        return []
    beta = math.acos(min(1.0, max(-1.0, c)))
    out = []
    for bb in (beta, -beta):
        alpha = math.degrees(_phase(z) - _phase(complex(a + b * math.cos(bb), b * math.sin(bb))))
        bd = math.degrees(bb)
        out.append((alpha % 360.0, 180.0 if bd <= -180.0 else bd))
    return out


def _phase(z: complex) -> float:
    return math.atan2(z.imag, z.real)


def _into(x: float, lo: float, hi: float) -> float | None:
    """``x + 360k`` inside ``[lo, hi]`` (the least such), or ``None``."""
    y = x + 360.0 * math.ceil((lo - x) / 360.0)
    return y if y <= hi else None


def side_angles(name: str, conf: dict, kin: dict, lengths: tuple[float, ...],
                bases: np.ndarray) -> list[tuple[float, float]]:
    """A ``start`` or ``target`` object (``alpha_beta_deg`` or ``xy_mm``) → per robot the exact
    ``(α, β)`` in degrees (module docstring); ``lengths``: the arms, ``bases`` complex."""
    n = len(bases)
    blo, bhi = (float(x) for x in kin.get("beta_range", (0.0, 180.0)))
    arange = kin.get("alpha_range")
    alo, ahi = (0.0, 360.0) if arange is None else (float(arange[0]), float(arange[1]))
    rows = []
    if "alpha_beta_deg" in conf:
        pairs = conf["alpha_beta_deg"]
        if len(pairs) != n:
            raise OracleInputError(f"{name} has {len(pairs)} angle pairs for {n} positioners", value=pairs)
        for a, b in pairs:
            a, b = float(a), float(b)
            if arange is None:
                a %= 360.0
            elif not alo <= a <= ahi:
                raise OracleInputError(f"{name}: alpha {a} outside [{alo}, {ahi}]", value=a)
            if not blo <= b <= bhi:
                raise OracleInputError(f"{name}: beta {b} outside [{blo}, {bhi}]", value=b)
            rows.append((a, b))
        return rows
    if "xy_mm" not in conf:
        raise OracleInputError(f"{name} must hold 'alpha_beta_deg' or 'xy_mm'", value=sorted(conf))
    hand = conf.get("handedness", "any")
    if hand not in HANDEDNESS:
        raise OracleInputError(f"{name}: unknown handedness {hand!r}", value=hand)
    pts = conf["xy_mm"]
    if len(pts) != n:
        raise OracleInputError(f"{name} has {len(pts)} fibre positions for {n} positioners", value=pts)
    for p, (x, y) in enumerate(pts):
        sols = fibre_inverse(lengths[0], lengths[1], complex(float(x), float(y)) - bases[p])
        if not sols:
            raise OracleInputError(f"{name}: fibre position {[x, y]} out of robot {p}'s reach", value=[x, y])
        options = sols[:1] if hand == "right" else sols[1:] if hand == "left" else sols
        found = None
        for a, b in options:
            b2 = _into(b, blo, bhi)
            a2 = a if arange is None else _into(a, alo, ahi)
            if a2 is not None and b2 is not None:
                found = (a2, b2)
                break
        if found is None:
            raise OracleInputError(f"{name}: the {hand} solution for robot {p} leaves the joint ranges", value=[x, y])
        rows.append(found)
    return rows
