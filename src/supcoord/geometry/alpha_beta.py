"""The alpha-beta robot (SDSS-V-like, 2 DOF): uniform or per-robot joint lattices.

Geometry (``docs/formats.md``), angles from +x, counter-clockwise positive: the elbow at
``alpha·(cos α, sin α)``; the colliding segment ``[p0, p1]`` given in the beta arm's frame
(origin at the elbow, +x along the arm at ``α + β``), by default the beta arm from the
elbow to the fibre ``((0, 0), (beta, 0))``.  Positions are ``(i, j)`` indices into the
joints' lattices (:mod:`.lattice`); motion between them is linear in angle.

References
----------
- C. Sayres et al., kaiju: collision-avoidance path planning for SDSS-V robots (alpha-beta,
  the beta arm's collision segment); ``docs/instruments.md``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InputError
from .chain import chain_angles_deg, chain_segments
from .joint_space import MAX_LENGTH, MAX_POSITIONS, Joint, Kinematics, _is_int
from .lattice import angle_table as _angle_table
from .lattice import interpolate as _interp
from .lattice import joint_range as _joint_range
from .lattice import points as _points
from .layout import _positive_number

__all__ = ["AlphaBeta"]


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
    - ``offsets = (α₀, β₀)`` (degrees): a robot's calibration, the joint angles it is commanded
      (its lattice, ranges, starts, targets and plans) turn its arms to ``α + α₀`` and
      ``β + β₀`` from +x and from the alpha arm (SDSS-V's ``alphaOffset``, ``betaOffset``,
      with the hole's frame turn folded into ``α₀``).

    >>> kin = AlphaBeta(7.4, 15.0, 4, 3, (0.0, 180.0))
    >>> kin.segments([1, 0]).round(6).tolist()   # α = 90°, β = 0: arm straight up +y
    [[0.0, 7.4], [0.0, 22.4]]
    """

    kind = "alpha-beta"

    def __init__(self, alpha: float, beta: float, alpha_steps: int, beta_steps: int,
                 beta_range: tuple[float, float] = (0.0, 180.0), *, alpha_range: Any = None,
                 alpha_deg: Any = None, beta_deg: Any = None, segment: Any = None, fibre_point: Any = None,
                 offsets: Any = None):
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
        self.offsets = None if offsets is None else tuple(float(v) for v in _points([offsets], "offsets", 1)[0])
        self._key: tuple | None = None
        self._cache: dict = {}  # reach and the largest steps (an AlphaBeta does not change once made)

    def __repr__(self) -> str:
        extra = "".join(f", {k}={v!r}" for k, v in self._options().items())
        return (f"AlphaBeta(alpha={self.alpha}, beta={self.beta}, alpha_steps={self.alpha_steps}, "
                f"beta_steps={self.beta_steps}, beta_range={list(self.beta_range)}{extra})")

    def _options(self) -> dict:
        out: dict = {}
        for name in ("alpha_range", "alpha_deg", "beta_deg", "segment", "fibre_point", "offsets"):
            v = getattr(self, name)
            if v is not None:
                out[name] = np.asarray(v).tolist()
        return out

    def key(self) -> tuple:
        """Every number the geometry depends on (equal keys: identical robots); computed once
        (an AlphaBeta does not change after it is made)."""
        if self._key is None:
            self._key = (self.alpha, self.beta, self.alpha_steps, self.beta_steps, self.beta_range,
                         tuple((k, _freeze(v)) for k, v in self._options().items()))
        return self._key

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
        if self.offsets is not None:
            a, b = a + math.radians(self.offsets[0]), b + math.radians(self.offsets[1])
        return a, b

    def _max_step_rad(self, joint: int) -> float:
        """The largest turn of one move of ``joint`` (radians; computed once per joint)."""
        if joint not in self._cache:
            self._cache[joint] = self._largest_step(joint)
        return self._cache[joint]

    def _largest_step(self, joint: int) -> float:
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
        where ``cos(β + φ_p)`` is over ``[lo, hi]`` (``φ_p`` the polar angle of ``p``); computed once."""
        if "reach" not in self._cache:
            self._cache["reach"] = self._farthest()
        return self._cache["reach"]

    def _farthest(self) -> float:
        ends = [(0.0, 0.0), (self.beta, 0.0)] if self.segment is None else [tuple(p) for p in self.segment]
        out = 0.0
        for px, py in ends:
            r, phi = math.hypot(px, py), math.atan2(py, px)
            lo, hi = np.radians(np.add(self.beta_range, 0.0 if self.offsets is None else self.offsets[1])) + phi
            # max over β ∈ [lo, hi] of cos β: 1 if a multiple of 2π lies inside, else at an end
            k = math.ceil(lo / (2 * math.pi))
            cmax = 1.0 if 2 * math.pi * k <= hi else max(math.cos(lo), math.cos(hi))
            out = max(out, math.sqrt(max(0.0, self.alpha**2 + r**2 + 2 * self.alpha * r * cmax)))
        return out

    def segments(self, q: Any) -> np.ndarray:
        a, b = self.angles(q)
        return self._segments_at(a, b)

    def chain(self) -> tuple[float, tuple[tuple[float, float], tuple[float, float]]]:
        """The alpha arm, then the colliding segment in the beta arm's frame."""
        (x0, y0), (x1, y1) = ((0.0, 0.0), (self.beta, 0.0)) if self.segment is None else self.segment
        return self.alpha, ((float(x0), float(y0)), (float(x1), float(y1)))

    def chain_angles(self, q: Any) -> tuple[np.ndarray, np.ndarray]:
        return self.angles(q)

    def segments_at_deg(self, angles_deg: Any) -> np.ndarray:
        """The colliding segment (relative to the base) at joint angles ``(α, β)`` in degrees
        ``(..., 2)``, any angles (not only the positions')."""
        return self._segments_at(*chain_angles_deg(angles_deg, self.chain_offsets_deg()))

    def chain_offsets_deg(self) -> tuple[float, ...]:
        return (0.0, 0.0) if self.offsets is None else self.offsets

    def _segments_at(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        l1, seg = self.chain()
        return chain_segments(l1, seg, a, b)

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
            a_deg, b_deg = math.degrees(a), math.degrees(b)
            if self.offsets is not None:  # the commanded angles
                a_deg, b_deg = a_deg - self.offsets[0], b_deg - self.offsets[1]
            b_deg = (b_deg + 180.0) % 360.0 - 180.0
            out.append((a_deg % 360.0, 180.0 if b_deg == -180.0 else b_deg))
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


def _freeze(v: Any) -> Any:
    return tuple(_freeze(x) for x in v) if isinstance(v, list) else v
