"""Starts and targets as users have them: joint angles or fibre positions, held exactly.

A PROBLEM.json ``start`` or ``target`` is a list of discrete positions (indices into the
kinematics' lattice), or (``docs/formats.md``, extensions for real instruments)

- ``{"alpha_beta_deg": [[α, β], ...]}``: joint angles in degrees, one pair per robot;
- ``{"xy_mm": [[x, y], ...], "handedness": "right" | "left" | "any"}``: fibre positions
  in the focal plane (mm), turned into joint angles by inverse kinematics
  (:meth:`~supcoord.geometry.kinematics.AlphaBeta.inverse_deg`): ``right`` is the elbow
  solution with the fibre turned counter-clockwise from the alpha arm (``β + φ_f`` in
  [0°, 180°], SDSS-V's working range), ``left`` the other, ``any`` (the default) the
  first of them inside the joint ranges.

**No snapping.**  When a start or target is given by angles, every robot gets its own
lattice (:func:`~supcoord.geometry.kinematics.exact_lattice`): the shared uniform
positions, with the ones nearest to the robot's start and target angles replaced by those
angles exactly.  The plan then starts and ends at the exact angles, and every verdict
(a plan, or a certificate that none exists) is about robots moving along their own
lattices: at most two uniform steps per move, each joint turning linearly between
neighbouring positions.

Every mistake is one line naming the field, the robot and the value: an angle outside a
joint's range, a fibre position out of a robot's reach (with the distance and the reachable
annulus), a handedness whose solution leaves the beta range.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from ..geometry.kinematics import AlphaBeta, Kinematics, _is_int, exact_lattice
from ..geometry.layout import _finite_number, _short

__all__ = ["ANGLE_FORMS", "HANDEDNESS", "parse_positions", "parse_offline", "read_fixed", "fixed_targets", "with_angles", "robot_lattices",
           "radian_warnings"]

#: the object forms of a start or target (besides a list of indices)
ANGLE_FORMS = ("alpha_beta_deg", "xy_mm")
HANDEDNESS = ("right", "left", "any")


def parse_positions(value: Any, name: str, n: int, kin: Kinematics, bases: np.ndarray, where: str | None,
                    robots: list[AlphaBeta] | None = None) -> np.ndarray | list[tuple[float, float]]:
    """A start or target: ``(n, J)`` index positions, or ``n`` exact ``(α, β)`` in degrees
    (``robots``: each robot's own kinematics, for its inverse kinematics)."""
    if isinstance(value, list):
        if len(value) != n:
            raise FormatError(f"{name} has {len(value)} positions but the layout has {n} positioners",
                              value=len(value), where=where)
        rows = [kin.position_from_json(v, f"{name}[{i}]", where) for i, v in enumerate(value)]
        return np.array(rows, dtype=int).reshape(n, kin.n_joints)
    if not isinstance(value, dict):
        raise FormatError(f"{name} must be a list of {n} positions or an object with 'alpha_beta_deg' or "
                          f"'xy_mm', got {_short(value)}", value=value, where=where)
    forms = [k for k in ANGLE_FORMS if k in value]
    extra = sorted(set(value) - set(ANGLE_FORMS) - {"handedness", "fibre"})  # "fibre": problem_fibre's
    if len(forms) != 1 or extra:
        raise FormatError(f"{name} must hold exactly one of 'alpha_beta_deg' or 'xy_mm' (and 'handedness' with "
                          f"'xy_mm', 'fibre'), got the fields {sorted(map(str, value))}", value=sorted(map(str, value)),
                          where=where)
    if not isinstance(kin, AlphaBeta):
        raise InputError(f"{name}.{forms[0]} needs alpha-beta kinematics, got {kin.kind!r}", value=kin.kind,
                         where=where)
    form = forms[0]
    rows = value[form]
    if not isinstance(rows, list) or len(rows) != n:
        got = f"{len(rows)} entries" if isinstance(rows, list) else _short(rows)
        raise FormatError(f"{name}.{form} must be a list of {n} pairs, got {got}", value=rows, where=where)
    for i, r in enumerate(rows):
        if not (isinstance(r, list) and len(r) == 2 and all(_finite_number(v) for v in r)):
            raise FormatError(f"{name}.{form}[{i}] must be a pair of finite numbers, got {_short(r)}", value=r,
                              where=where)
    if form == "alpha_beta_deg":
        if "handedness" in value:
            raise FormatError(f"{name}.handedness applies to 'xy_mm' only", value=value["handedness"], where=where)
        return [_in_ranges(kin, float(a), float(b), f"{name}.alpha_beta_deg[{i}]", where)
                for i, (a, b) in enumerate(rows)]
    hand = value.get("handedness", "any")
    if hand not in HANDEDNESS:
        raise InputError(f"{name}.handedness must be one of {', '.join(HANDEDNESS)}, got {_short(hand)}", value=hand,
                         where=where)
    return [_inverse(kin if robots is None else robots[i], np.asarray(xy, float) - bases[i], hand,
                     f"{name}.xy_mm[{i}]", xy, where) for i, xy in enumerate(rows)]


def radian_warnings(data: Any, where: str | None) -> list[str]:
    """A warning for each ``start``/``target`` whose ``alpha_beta_deg`` looks like radians.

    The rule: every angle lies within ±2π, at least one is not a whole number and at least
    one is not zero.  Degrees that look so are rare (every robot within 6.3° of α = 0 and of
    β = 0), radians almost always do; the angles are still read as degrees.
    """
    out = []
    for name in ("start", "target"):
        value = data.get(name) if isinstance(data, dict) else None
        rows = value.get("alpha_beta_deg") if isinstance(value, dict) else None
        if not isinstance(rows, list) or not rows:
            continue
        x = np.array([v for r in rows if isinstance(r, list) for v in r if _finite_number(v)], dtype=float)
        if len(x) and np.all(np.abs(x) <= 2 * math.pi) and np.any(x != np.round(x)) and np.any(x != 0):
            prefix = f"{where}: " if where else ""
            out.append(f"{prefix}{name}.alpha_beta_deg: every angle is within ±2π (largest |angle| "
                       f"{float(np.abs(x).max()):.4g}) and some are fractional: radians? They are read as degrees")
    return out


def parse_offline(value: Any, n: int, kin: Kinematics, where: str | None,
                  robots: list[AlphaBeta] | None = None) -> dict[int, tuple[float, float]]:
    """``"offline": {"robot index": [α, β], ...}``: robots held at those angles."""
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise FormatError(f"offline must be an object {{\"robot index\": [alpha, beta], ...}}, got {_short(value)}",
                          value=value, where=where)
    if not isinstance(kin, AlphaBeta):
        raise InputError(f"offline needs alpha-beta kinematics, got {kin.kind!r}", value=kin.kind, where=where)
    out: dict[int, tuple[float, float]] = {}
    for key, ab in value.items():
        # ASCII decimal digits only (str.isdigit also takes '²', '٣', '３'), and no longer than an index can be
        if not (isinstance(key, str) and re.fullmatch(r"[0-9]{1,18}", key) and int(key) < n):
            raise InputError(f"offline: {_short(key)} is not a robot index in [0, {n - 1}]", value=key, where=where)
        if not (isinstance(ab, list) and len(ab) == 2 and all(_finite_number(v) for v in ab)):
            raise FormatError(f"offline.{key} must be [alpha, beta] in degrees, got {_short(ab)}", value=ab, where=where)
        p = int(key)
        if p in out:
            raise InputError(f"offline: robot {p} is given twice ({_short(key)} and another spelling)", value=key,
                             where=where)
        out[p] = _in_ranges(kin if robots is None else robots[p], float(ab[0]), float(ab[1]), f"offline.{key}", where)
    return out

def read_fixed(value: Any, n: int, where: str | None) -> list[int]:
    """PROBLEM.json's ``"fixed": [robot, ...]`` (robot indices from 0): the robots kept at their start.

    >>> read_fixed([3, 1], 7, None)
    [1, 3]
    >>> read_fixed([9], 7, "p.json")
    Traceback (most recent call last):
    ...
    supcoord.errors.InputError: p.json: fixed[0]: 9 is not a robot index in [0, 6]
    """
    if value is None:
        return []
    if not isinstance(value, list):
        raise FormatError(f"fixed must be a list of robot indices, got {_short(value)}", value=value, where=where)
    out: set[int] = set()
    for i, p in enumerate(value):
        if not _is_int(p) or not 0 <= p < n:
            raise InputError(f"fixed[{i}]: {_short(p)} is not a robot index in [0, {n - 1}]", value=p, where=where)
        if p in out:
            raise InputError(f"fixed[{i}]: robot {p} is listed twice", value=p, where=where)
        out.add(int(p))
    return sorted(out)


def fixed_targets(start: Any, target: Any, fixed: list[int], kin: Kinematics,
                  robots: list | None = None) -> Any:
    """``target`` with each robot of ``fixed`` at its ``start`` (index arrays, or lists of
    exact ``(α, β)`` degrees as :mod:`.targets` reads them)."""
    if not fixed:
        return target
    if isinstance(start, np.ndarray) and isinstance(target, np.ndarray):
        out = target.copy()
        out[fixed] = start[fixed]
        return out
    at_start = {p: (tuple(float(v) for v in (kin if robots is None else robots[p]).joint_angles_deg(start[p]))
                    if isinstance(start, np.ndarray) else start[p]) for p in fixed}
    return with_angles(target, at_start, kin, robots)  # type: ignore[arg-type]


def with_angles(conf: Any, fixed: dict[int, tuple[float, float]], kin: AlphaBeta,
                robots: list[AlphaBeta] | None = None) -> list[tuple[float, float]]:
    """A start or target as exact angles per robot, with the robots in ``fixed`` at theirs."""
    out = []
    for p in range(len(conf)):
        if p in fixed:
            out.append(fixed[p])
        elif isinstance(conf, np.ndarray):
            k = kin if robots is None else robots[p]
            out.append(tuple(float(v) for v in k.joint_angles_deg(conf[p])))
        else:
            out.append(conf[p])
    return out


def _in_ranges(kin: AlphaBeta, a: float, b: float, field: str, where: str | None) -> tuple[float, float]:
    """``(α, β)`` inside the joint ranges (a wrapping alpha taken into [0, 360)), or an error."""
    if kin.alpha_range is None:
        a = a % 360.0
    else:
        lo, hi = kin.alpha_range
        if not lo <= a <= hi:
            raise InputError(f"{field}: alpha {a:g} deg is outside the alpha range [{lo:g}, {hi:g}]", value=a,
                             where=where)
    lo, hi = kin.beta_range
    if not lo <= b <= hi:
        raise InputError(f"{field}: beta {b:g} deg is outside the beta range [{lo:g}, {hi:g}]", value=b, where=where)
    return a, b


def _shift_into(x: float, lo: float, hi: float) -> float | None:
    """``x + 360k`` inside ``[lo, hi]``, or ``None``."""
    k = math.ceil((lo - x) / 360.0)
    y = x + 360.0 * k
    return y if y <= hi else None


def _inverse(kin: AlphaBeta, rel: np.ndarray, hand: str, field: str, xy: Any, where: str | None) -> tuple[float, float]:
    sols = kin.inverse_deg(rel)
    if not sols:
        lo, hi = kin.fibre_radius_range()
        raise InputError(f"{field}: fibre position {[float(v) for v in xy]} is {math.hypot(*rel):.3f} mm from the "
                         f"robot's base, outside its reach [{lo:.3f}, {hi:.3f}] mm", value=xy, where=where)
    options = sols[:1] if hand == "right" else sols[1:] if hand == "left" else sols
    for a, b in options:
        b2 = _shift_into(b, *kin.beta_range)
        a2 = a if kin.alpha_range is None else _shift_into(a, *kin.alpha_range)
        if a2 is not None and b2 is not None:
            return a2, b2
    a, b = options[0]
    raise InputError(f"{field}: the {hand if hand != 'any' else 'either'}-handed solution (alpha {a:.3f}, beta "
                     f"{b:.3f} deg) is outside the joint ranges (alpha {list(kin.alpha_range or (0, 360))}, beta "
                     f"{list(kin.beta_range)})", value=xy, where=where)


def robot_lattices(kin: AlphaBeta, start: Any, target: Any,
                   robots: list[AlphaBeta] | None = None) -> tuple[list[AlphaBeta], np.ndarray, np.ndarray]:
    """Each robot's own lattice holding its exact start and target angles (module docstring):
    ``(kinematics per robot, start indices, target indices)``.  ``start``/``target`` are
    index arrays or lists of exact ``(α, β)``; ``robots``: each robot's own arms (else
    ``kin``'s); robots with equal geometry and lattices share one object."""
    n = len(start)
    wraps = kin.alpha_range is None
    grids = (kin.lattice_deg(0), kin.lattice_deg(1))

    def angles(conf: Any, p: int) -> tuple[float, float]:
        if isinstance(conf, np.ndarray):
            return tuple(float(v) for v in base(p).joint_angles_deg(conf[p]))  # type: ignore[return-value]
        return conf[p]

    def base(p: int) -> AlphaBeta:
        return kin if robots is None else robots[p]

    shared: dict[tuple, AlphaBeta] = {}
    kins: list[AlphaBeta] = []
    s_idx = np.zeros((n, 2), dtype=int)
    t_idx = np.zeros((n, 2), dtype=int)
    for p in range(n):
        (sa, sb), (ta, tb) = angles(start, p), angles(target, p)
        tab_a, (s_idx[p, 0], t_idx[p, 0]) = exact_lattice(grids[0], [sa, ta], wraps)
        tab_b, (s_idx[p, 1], t_idx[p, 1]) = exact_lattice(grids[1], [sb, tb], False)
        k = base(p)
        key = (tab_a.tobytes(), tab_b.tobytes(), k.key())
        if key not in shared:
            shared[key] = AlphaBeta(k.alpha, k.beta, k.alpha_steps, k.beta_steps, k.beta_range,
                                    alpha_range=k.alpha_range, alpha_deg=tab_a, beta_deg=tab_b,
                                    segment=k.segment, fibre_point=k.fibre_point, offsets=k.offsets)
        kins.append(shared[key])
    return kins, s_idx, t_idx
