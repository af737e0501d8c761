"""Discretised positioner kinematics: joint positions → the colliding segment.

Positions and single moves are those of :mod:`.joint_space` (re-exported here); a move
is one of the supervisor's single events.

Geometry (``docs/formats.md``), angles from +x, counter-clockwise positive:

- ``rotary`` (the seed paper's 1-DOF positioner): ``θ(k) = −2πk/steps``; the arm, the
  colliding segment, goes from the base to ``arm·(cos θ, sin θ)``; index ``k + 1`` is
  one step clockwise (the paper's forward event ``v``); ``steps − 1`` and ``0`` are
  neighbours.
- ``alpha-beta`` (SDSS-V-like, 2 DOF): ``α(i) = 2πi/A`` (wrapping),
  ``β(j) = lo + (hi − lo)·j/(B − 1)`` with hard stops at ``j = 0`` and ``j = B − 1``; the
  elbow at ``alpha·(cos α, sin α)``; the beta arm, the colliding segment, from the
  elbow to the fibre ``elbow + beta·(cos(α+β), sin(α+β))``.

Motion between positions is linear in joint space: :meth:`Kinematics.segments`
accepts fractional joint positions, so ``q + t·δ`` for ``t ∈ [0, 1]`` is the pose at
time ``t`` of a step, and :meth:`Kinematics.sweep_length` bounds how far any point of
the colliding segment travels along it (what makes sampled swept checks sound).

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, Supervisory coordination of robotic fiber
  positioners in multi-object spectrographs, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (rotary model).
- C. Sayres et al., kaiju: collision-avoidance path planning for SDSS-V robots (alpha-beta).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import FormatError, InputError
from .joint_space import Joint, Kinematics, _is_int
from .layout import _finite_number, _positive_number, _short

__all__ = ["Joint", "Kinematics", "Rotary", "AlphaBeta", "exact_lattice", "kinematics_from_spec", "MAX_LENGTH",
           "MAX_POSITIONS"]

#: longest arm accepted (mm); anything longer is a unit mistake
MAX_LENGTH = 1e6
#: most positions of one positioner: a pair's collision tables hold positions² entries, and
#: :data:`supcoord.geometry.collision.MAX_TABLE_ENTRIES` is ``MAX_POSITIONS²`` (5·10⁷)
MAX_POSITIONS = 7071


class Rotary(Kinematics):
    """The seed paper's one-joint positioner: ``θ(k) = −2πk/steps``, the arm from base to fibre.

    >>> kin = Rotary(15.0, 12)
    >>> kin.segments([3]).round(6).tolist()   # k = 3: a quarter turn clockwise, pointing −y
    [[0.0, 0.0], [0.0, -15.0]]
    """

    kind = "rotary"

    def __init__(self, arm: float, steps: int):
        if not _positive_number(arm) or arm > MAX_LENGTH:
            raise InputError(f"kinematics.arm must be a positive number (mm) <= {MAX_LENGTH:g}, got {arm!r}", value=arm)
        if not _is_int(steps) or steps < 2:
            raise InputError(f"kinematics.steps must be an integer >= 2, got {steps!r}", value=steps)
        if steps > MAX_POSITIONS:
            raise InputError(f"kinematics.steps must be at most {MAX_POSITIONS} (a pair's collision tables hold "
                             f"steps² entries), got {steps}", value=steps)
        self.arm = float(arm)
        self.steps = int(steps)
        self.joints = (Joint("theta", self.steps, True),)

    def __repr__(self) -> str:
        return f"Rotary(arm={self.arm}, steps={self.steps})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Rotary) and (self.arm, self.steps) == (other.arm, other.steps)

    __hash__ = None  # type: ignore[assignment]

    @property
    def reach(self) -> float:
        return self.arm

    def theta(self, q: Any) -> np.ndarray:
        """``θ = −2πk/steps`` in radians for (fractional) positions ``q`` ``(..., 1)``."""
        q = np.asarray(q, dtype=float)
        return -2 * np.pi * q[..., 0] / self.steps

    def segments(self, q: Any) -> np.ndarray:
        return self._segments_at(self.theta(q))

    def joint_angles_deg(self, q: Any) -> np.ndarray:
        """``θ`` in degrees (``(..., 1)``) for (fractional) positions ``q``: ``−360·k/steps``."""
        q = np.asarray(q, dtype=float)
        return -360.0 * q / self.steps

    def segments_at_deg(self, angles_deg: Any) -> np.ndarray:
        """The arm (relative to the base) at angles ``θ`` in degrees ``(..., 1)``."""
        return self._segments_at(np.radians(np.asarray(angles_deg, dtype=float)[..., 0]))

    def _segments_at(self, theta: np.ndarray) -> np.ndarray:
        end = self.arm * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
        return np.stack([np.zeros_like(end), end], axis=-2)

    def sweep_length(self, delta: Any) -> np.ndarray:
        delta = np.asarray(delta, dtype=float)
        return self.arm * np.abs(delta[..., 0]) * 2 * np.pi / self.steps

    def rotation(self, q: Any, joint: int, delta: Any) -> tuple[np.ndarray, np.ndarray]:
        q = np.asarray(q, dtype=float)
        angle = -2 * np.pi * np.broadcast_to(np.asarray(delta, float), q.shape[:-1]) / self.steps
        return np.zeros(q.shape[:-1] + (2,)), angle

    def to_json(self) -> dict:
        return {"kind": "rotary", "arm": self.arm, "steps": self.steps}


class AlphaBeta(Kinematics):
    """Two joints (SDSS-V-like): ``α = 2πi/A`` wrapping, ``β = lo + (hi−lo)·j/(B−1)`` with hard stops.

    Options for real robots (``docs/formats.md``, extensions for real instruments):

    - ``alpha_range = (lo, hi)`` (degrees): the alpha joint has hard stops and does not wrap;
      its positions are ``lo + (hi − lo)·i/(A − 1)``.
    - ``alpha_deg`` / ``beta_deg``: explicit joint angles of the positions (degrees,
      strictly increasing, inside the joint's range; for a wrapping alpha joint less than a
      turn from the first to the last), a robot's own lattice holding its exact start and
      target (:func:`exact_lattice`).  Between neighbouring positions a joint turns linearly.
    - ``segment = ((x0, y0), (x1, y1))``: the colliding segment in the beta arm's frame
      (origin at the elbow, +x along the arm), default ``((0, 0), (beta, 0))``;
      ``fibre_point``: the fibre in that frame, default ``(beta, 0)``.

    >>> kin = AlphaBeta(7.4, 15.0, 4, 3, (0.0, 180.0))
    >>> kin.segments([1, 0]).round(6).tolist()   # α = 90°, β = 0: arm straight up +y
    [[0.0, 7.4], [0.0, 22.4]]
    """

    kind = "alpha-beta"

    def __init__(self, alpha: float, beta: float, alpha_steps: int, beta_steps: int,
                 beta_range: tuple[float, float] = (0.0, 180.0), *, alpha_range: Any = None,
                 alpha_deg: Any = None, beta_deg: Any = None, segment: Any = None, fibre_point: Any = None):
        for name, v in (("alpha", alpha), ("beta", beta)):
            if not _positive_number(v) or v > MAX_LENGTH:
                raise InputError(f"kinematics.{name} must be a positive arm length (mm) <= {MAX_LENGTH:g}, got {v!r}", value=v)
        if not _is_int(alpha_steps) or alpha_steps < 2:
            raise InputError(f"kinematics.alpha_steps must be an integer >= 2, got {alpha_steps!r}", value=alpha_steps)
        if not _is_int(beta_steps) or beta_steps < 2:
            raise InputError(f"kinematics.beta_steps must be an integer >= 2, got {beta_steps!r}", value=beta_steps)
        if alpha_steps * beta_steps > MAX_POSITIONS:
            raise InputError(f"kinematics.alpha_steps × beta_steps must be at most {MAX_POSITIONS} positions (a "
                             f"pair's collision tables hold positions² entries), got {alpha_steps} × {beta_steps}",
                             value=[alpha_steps, beta_steps])
        lo, hi = _joint_range(beta_range, "beta_range")
        self.alpha, self.beta = float(alpha), float(beta)
        self.alpha_steps, self.beta_steps = int(alpha_steps), int(beta_steps)
        self.beta_range = (lo, hi)
        self.alpha_range = None if alpha_range is None else _joint_range(alpha_range, "alpha_range")
        self.joints = (Joint("alpha", self.alpha_steps, self.alpha_range is None),
                       Joint("beta", self.beta_steps, False))
        self.alpha_deg = None if alpha_deg is None else _angle_table(alpha_deg, "alpha", self.alpha_steps,
                                                                     self.alpha_range, wraps=self.alpha_range is None)
        self.beta_deg = None if beta_deg is None else _angle_table(beta_deg, "beta", self.beta_steps, self.beta_range,
                                                                   wraps=False)
        self.segment = None if segment is None else _points(segment, "segment", 2)
        self.fibre_point = None if fibre_point is None else _points([fibre_point], "fibre_point", 1)[0]

    def __repr__(self) -> str:
        extra = "".join(f", {k}={v!r}" for k, v in self._options().items())
        return (f"AlphaBeta(alpha={self.alpha}, beta={self.beta}, alpha_steps={self.alpha_steps}, "
                f"beta_steps={self.beta_steps}, beta_range={list(self.beta_range)}{extra})")

    def _options(self) -> dict:
        out: dict = {}
        for name in ("alpha_range", "alpha_deg", "beta_deg", "segment", "fibre_point"):
            v = getattr(self, name)
            if v is not None:
                out[name] = np.asarray(v).tolist()
        return out

    def key(self) -> tuple:
        """Every number the geometry depends on (equal keys: identical robots)."""
        return (self.alpha, self.beta, self.alpha_steps, self.beta_steps, self.beta_range,
                tuple((k, _freeze(v)) for k, v in self._options().items()))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, AlphaBeta) and self.key() == other.key()

    __hash__ = None  # type: ignore[assignment]

    # --- the joints' angles ----------------------------------------------------------
    def lattice_deg(self, joint: int) -> np.ndarray:
        """The angles (degrees) of the positions of ``joint`` (0: alpha, 1: beta)."""
        if joint == 0:
            if self.alpha_deg is not None:
                return self.alpha_deg.copy()
            if self.alpha_range is None:
                return 360.0 * np.arange(self.alpha_steps) / self.alpha_steps
            lo, hi = self.alpha_range
            return lo + (hi - lo) * np.arange(self.alpha_steps) / (self.alpha_steps - 1)
        if self.beta_deg is not None:
            return self.beta_deg.copy()
        lo, hi = self.beta_range
        return lo + (hi - lo) * np.arange(self.beta_steps) / (self.beta_steps - 1)

    def joint_angles_deg(self, q: Any) -> np.ndarray:
        """``(α, β)`` in degrees for (fractional) positions ``q`` ``(..., 2)``: the positions'
        own angles (exact where a lattice holds a given angle), linear in between."""
        q = np.asarray(q, dtype=float)
        return np.stack([self._joint_deg(q[..., 0], 0), self._joint_deg(q[..., 1], 1)], axis=-1)

    def _joint_deg(self, x: np.ndarray, joint: int) -> np.ndarray:
        table = self.alpha_deg if joint == 0 else self.beta_deg
        if table is None:
            tab = self.lattice_deg(joint)
            if joint == 0 and self.alpha_range is None:
                return 360.0 * x / self.alpha_steps
            lo, hi = (self.alpha_range if joint == 0 else self.beta_range)
            return lo + (hi - lo) * x / (len(tab) - 1)
        return _interp(x, table, wraps=joint == 0 and self.alpha_range is None)

    def angles(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(α, β)`` in radians for (fractional) positions ``q``."""
        q = np.asarray(q, dtype=float)
        if self.alpha_deg is None and self.alpha_range is None:
            a = 2 * np.pi * q[..., 0] / self.alpha_steps
        elif self.alpha_deg is None:
            alo, ahi = np.radians(self.alpha_range)
            a = alo + (ahi - alo) * q[..., 0] / (self.alpha_steps - 1)
        else:
            a = np.radians(self._joint_deg(q[..., 0], 0))
        if self.beta_deg is None:
            lo, hi = np.radians(self.beta_range)
            b = lo + (hi - lo) * q[..., 1] / (self.beta_steps - 1)
        else:
            b = np.radians(self._joint_deg(q[..., 1], 1))
        return a, b

    def _max_step_rad(self, joint: int) -> float:
        """The largest turn of one move of ``joint`` (radians)."""
        table = self.alpha_deg if joint == 0 else self.beta_deg
        if table is None:
            if joint == 0 and self.alpha_range is None:
                return 2 * np.pi / self.alpha_steps
            lo, hi = self.alpha_range if joint == 0 else self.beta_range
            return math.radians(hi - lo) / (len(self.lattice_deg(joint)) - 1)
        steps = np.diff(table)
        if joint == 0 and self.alpha_range is None:
            steps = np.append(steps, table[0] + 360.0 - table[-1])
        return math.radians(float(steps.max()))

    @property
    def beta_step_rad(self) -> float:
        """The largest turn of one beta move (radians)."""
        return self._max_step_rad(1)

    # --- geometry ------------------------------------------------------------------
    @property
    def _segment_radius(self) -> float:
        """The farthest point of the colliding segment from the elbow (mm)."""
        if self.segment is None:
            return self.beta
        return float(np.hypot(self.segment[:, 0], self.segment[:, 1]).max())

    @property
    def reach(self) -> float:
        """The farthest point of the colliding segment from the base, over every ``β`` in the
        beta range: the distance from the base is convex along the segment, so it is at an
        end point ``p`` (beta-arm frame), at ``√(a² + |p|² + 2a|p|·cos(β + φ_p))``, largest
        where ``cos(β + φ_p)`` is over ``[lo, hi]`` (``φ_p`` the polar angle of ``p``)."""
        ends = [(0.0, 0.0), (self.beta, 0.0)] if self.segment is None else [tuple(p) for p in self.segment]
        out = 0.0
        for px, py in ends:
            r, phi = math.hypot(px, py), math.atan2(py, px)
            lo, hi = np.radians(self.beta_range) + phi
            # max over β ∈ [lo, hi] of cos β: 1 if a multiple of 2π lies inside, else at an end
            k = math.ceil(lo / (2 * math.pi))
            cmax = 1.0 if 2 * math.pi * k <= hi else max(math.cos(lo), math.cos(hi))
            out = max(out, math.sqrt(max(0.0, self.alpha**2 + r**2 + 2 * self.alpha * r * cmax)))
        return out

    def segments(self, q: Any) -> np.ndarray:
        a, b = self.angles(q)
        return self._segments_at(a, b)

    def segments_at_deg(self, angles_deg: Any) -> np.ndarray:
        """The colliding segment (relative to the base) at joint angles ``(α, β)`` in degrees
        ``(..., 2)``, any angles (not only the positions')."""
        angles = np.radians(np.asarray(angles_deg, dtype=float))
        return self._segments_at(angles[..., 0], angles[..., 1])

    def _segments_at(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        elbow = self.alpha * np.stack([np.cos(a), np.sin(a)], axis=-1)
        if self.segment is None:
            fibre = elbow + self.beta * np.stack([np.cos(a + b), np.sin(a + b)], axis=-1)
            return np.stack([elbow, fibre], axis=-2)
        c, s = np.cos(a + b)[..., None], np.sin(a + b)[..., None]
        (x0, y0), (x1, y1) = self.segment
        p0 = elbow + np.concatenate([x0 * c - y0 * s, x0 * s + y0 * c], axis=-1)
        p1 = elbow + np.concatenate([x1 * c - y1 * s, x1 * s + y1 * c], axis=-1)
        return np.stack([p0, p1], axis=-2)

    def fibre(self, q: Any) -> np.ndarray:
        if self.fibre_point is None and self.segment is None:
            return self.segments(q)[..., 1, :]
        a, b = self.angles(q)
        fx, fy = (self.beta, 0.0) if self.fibre_point is None else self.fibre_point
        elbow = self.alpha * np.stack([np.cos(a), np.sin(a)], axis=-1)
        c, s = np.cos(a + b), np.sin(a + b)
        return elbow + np.stack([fx * c - fy * s, fx * s + fy * c], axis=-1)

    def inverse_deg(self, xy: Any) -> list[tuple[float, float]]:
        """Joint angles ``(α, β)`` (degrees; ``α`` in [0, 360), ``β`` in (−180, 180]) that put
        the fibre at ``xy`` (mm, relative to the base): both elbow solutions, or none.

        With the fibre at ``f`` in the beta arm's frame (polar ``(ρ, φ)``) and ``d = |xy|``:
        ``d² = a² + ρ² + 2aρ·cos(β + φ)``, so ``β = ±acos((d² − a² − ρ²)/(2aρ)) − φ``, and ``α``
        turns ``(a, 0) + R(β)f`` onto ``xy``.  The ``+`` solution (``sin(β + φ) ≥ 0``, the
        fibre left of the alpha arm) comes first.  A point within 1e-9 mm of the reachable
        annulus' edge counts as on it.
        """
        x, y = (float(v) for v in xy)
        fx, fy = (self.beta, 0.0) if self.fibre_point is None else (float(v) for v in self.fibre_point)
        rho, phi = math.hypot(fx, fy), math.atan2(fy, fx)
        d2 = x * x + y * y
        c = (d2 - self.alpha**2 - rho**2) / (2 * self.alpha * rho)
        slack = 1e-9 * (math.sqrt(d2) + self.alpha + rho) / (self.alpha * rho)
        if abs(c) > 1 + slack:
            return []
        c = min(1.0, max(-1.0, c))
        out = []
        for sign in (+1, -1):
            b = sign * math.acos(c) - phi
            ex, ey = self.alpha + fx * math.cos(b) - fy * math.sin(b), fx * math.sin(b) + fy * math.cos(b)
            a = math.atan2(y, x) - math.atan2(ey, ex)
            b_deg = (math.degrees(b) + 180.0) % 360.0 - 180.0
            out.append((math.degrees(a) % 360.0, 180.0 if b_deg == -180.0 else b_deg))
        return out

    def fibre_radius_range(self) -> tuple[float, float]:
        """The closest and farthest fibre positions from the base over every ``β`` (mm)."""
        fx, fy = (self.beta, 0.0) if self.fibre_point is None else (float(v) for v in self.fibre_point)
        rho = math.hypot(fx, fy)
        return abs(self.alpha - rho), self.alpha + rho

    def sweep_length(self, delta: Any) -> np.ndarray:
        # a point of the colliding segment is within `reach` of the base (α turns it about the
        # base) and within the segment's radius of the elbow (β turns it about the elbow);
        # a move turns a joint by at most its largest step
        delta = np.asarray(delta, dtype=float)
        if self.alpha_deg is None and self.alpha_range is None:
            da = np.abs(delta[..., 0]) * 2 * np.pi / self.alpha_steps
        else:
            da = np.abs(delta[..., 0]) * self._max_step_rad(0)
        db = np.abs(delta[..., 1]) * self.beta_step_rad
        return self.reach * da + self._segment_radius * db

    def rotation(self, q: Any, joint: int, delta: Any) -> tuple[np.ndarray, np.ndarray]:
        # alpha turns the whole arm about the base; beta turns the beta arm about the elbow
        q = np.asarray(q, dtype=float)
        delta = np.broadcast_to(np.asarray(delta, float), q.shape[:-1])
        if joint == 0:
            centre = np.zeros(q.shape[:-1] + (2,))
            if self.alpha_deg is None and self.alpha_range is None:
                return centre, 2 * np.pi * delta / self.alpha_steps
            if self.alpha_deg is None:
                return centre, delta * self._max_step_rad(0)
            x = q[..., 0]
            return centre, np.radians(self._joint_deg(x + delta, 0) - self._joint_deg(x, 0))
        elbow = self.segments(q)[..., 0, :] if self.segment is None else \
            self.alpha * np.stack([np.cos(self.angles(q)[0]), np.sin(self.angles(q)[0])], axis=-1)
        if self.beta_deg is None:
            return elbow, delta * self.beta_step_rad
        x = q[..., 1]
        return elbow, np.radians(self._joint_deg(x + delta, 1) - self._joint_deg(x, 1))

    def to_json(self) -> dict:
        out = {"kind": "alpha-beta", "alpha": self.alpha, "beta": self.beta, "alpha_steps": self.alpha_steps,
               "beta_steps": self.beta_steps, "beta_range": list(self.beta_range)}
        if self.alpha_range is not None:
            out["alpha_range"] = list(self.alpha_range)
        return out


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


def _interp(x: np.ndarray, table: np.ndarray, wraps: bool) -> np.ndarray:
    """Piecewise-linear angle of fractional positions ``x`` over a lattice (degrees); a wrapping
    joint continues over ``[−1, n]`` (one step either way past the ends)."""
    n = len(table)
    if not wraps:
        return np.interp(x, np.arange(n), table)
    xp = np.arange(-1, n + 1)
    fp = np.concatenate([[table[-1] - 360.0], table, [table[0] + 360.0]])
    return np.interp(x, xp, fp)


def _joint_range(value: Any, name: str) -> tuple[float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 2 or not all(_finite_number(v) for v in value):
        raise InputError(f"kinematics.{name} must be [lo, hi] in degrees, got {_short(value)}", value=value)
    lo, hi = float(value[0]), float(value[1])
    if not (-360.0 <= lo < hi <= 360.0 and hi - lo <= 360.0):
        raise InputError(f"kinematics.{name} must satisfy -360 <= lo < hi <= 360 and hi - lo <= 360, got {[lo, hi]}",
                         value=value)
    return lo, hi


def _angle_table(value: Any, joint: str, steps: int, rng: tuple[float, float] | None, wraps: bool) -> np.ndarray:
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


def _points(value: Any, name: str, count: int) -> np.ndarray:
    pts = np.asarray(value, dtype=float)
    if pts.shape != (count, 2) or not np.all(np.isfinite(pts)) or np.abs(pts).max() > MAX_LENGTH:
        raise InputError(f"kinematics.{name} must be {count} point(s) [x, y] in mm, got {_short(value)}", value=value)
    pts.setflags(write=False)
    return pts


def _freeze(v: Any) -> Any:
    return tuple(_freeze(x) for x in v) if isinstance(v, list) else v


def kinematics_from_spec(spec: Any, where: str | None = None) -> Kinematics:
    """Parse a PROBLEM.json ``kinematics`` object; errors name the field and value."""
    if not isinstance(spec, dict):
        raise FormatError(f"kinematics must be an object, got {_short(spec)}", value=spec, where=where)
    kind = spec.get("kind")
    try:
        if kind == "rotary":
            _require(spec, ("arm", "steps"), where)
            _wrapping_steps(spec, "steps")
            return Rotary(spec["arm"], spec["steps"])
        if kind == "alpha-beta":
            _require(spec, ("alpha", "beta", "alpha_steps", "beta_steps"), where)
            if "alpha_range" not in spec:
                _wrapping_steps(spec, "alpha_steps")
            return AlphaBeta(spec["alpha"], spec["beta"], spec["alpha_steps"], spec["beta_steps"],
                             spec.get("beta_range", [0.0, 180.0]), alpha_range=spec.get("alpha_range"))
    except InputError as exc:
        if exc.where is None:
            exc.where = where
            exc.args = (exc.one_line(),)
        raise
    raise FormatError(f"kinematics.kind must be 'rotary' or 'alpha-beta', got {_short(kind)}", value=kind, where=where)


def _wrapping_steps(spec: dict, field: str) -> None:
    """A wrapping joint of a problem needs at least 3 steps: with 2, both moves reach the same
    position by opposite half-turns, so a plan's configurations cannot say which turn was
    made (and the way back would not retrace the way there)."""
    v = spec[field]
    if _is_int(v) and v == 2:
        raise InputError(f"kinematics.{field} must be at least 3 for a joint that wraps (with 2 steps both moves "
                         f"reach the same position by opposite half-turns), got 2", value=v)


def _require(spec: dict, fields: tuple[str, ...], where: str | None) -> None:
    for f in fields:
        if f not in spec:
            raise FormatError(f"kinematics.{f} is missing (kind {spec.get('kind')!r})", value=None, where=where)
