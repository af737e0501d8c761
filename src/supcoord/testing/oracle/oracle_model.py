"""A problem's JSON → the oracle's own geometry: bases, arms, buffers, positions.

Written again from ``docs/formats.md`` on purpose, sharing no code with
:mod:`supcoord.geometry` or :mod:`supcoord.problems` (it imports neither).  Points of
the plane are **complex numbers** ``x + iy`` throughout.

- **Hex layout** (``rings`` R, ``pitch`` p): the axial lattice point ``(u, v)`` is at
  ``p·(u + v·ω)`` with ``ω = e^{iπ/3}``.  Ring ``r`` is walked on the integers: from
  ``(r, 0)`` (its corner on ``+x``), ``r`` steps along each of the six axial
  directions ``(−1, +1), (−1, 0), (0, −1), (+1, −1), (+1, 0), (0, +1)`` in turn — the
  six edges counter-clockwise, corner ``k`` at angle ``60°·k``.  The centre comes first,
  then ring 1, 2, … (``1 + 3R(R+1)`` bases).  ``points`` layouts are taken as given.
- **Rotary** (``arm``, ``steps`` S): position ``k`` (fractional during a step) is the
  arm at angle ``θ = −2πk/S``; the colliding segment is ``[0, arm·e^{iθ}]`` (relative
  to the base); the joint wraps.
- **Alpha-beta** (``alpha`` a, ``beta`` b, ``alpha_steps`` A, ``beta_steps`` B,
  ``beta_range`` [lo, hi] degrees): ``α = 2πi/A`` (wraps), ``β = lo + (hi − lo)·j/(B − 1)``
  (hard stops); the colliding segment is ``[a·e^{iα}, a·e^{iα} + b·e^{i(α+β)}]``.
  With ``alpha_range`` [lo, hi] (degrees) the alpha joint has hard stops and does not wrap:
  ``α = lo + (hi − lo)·i/(A − 1)``.
- **Own lattices** (a ``start`` or ``target`` given as ``alpha_beta_deg`` or ``xy_mm``,
  :func:`.angles.exact_lattice`): every robot's joint positions are the uniform ones with the
  slots nearest to its start and target angles replaced by those angles exactly; a joint
  turns linearly in angle between neighbouring positions (:attr:`Arm.tables`).
- **Motion** between positions is linear in joint space: ``q + t·δ``, ``t ∈ [0, 1]``
  (with own lattices: linear in angle within each step, which is what a step is).
- **Levers** (what makes the swept check certified, :mod:`.certified_sweep`): turning joint ``j``
  by ``ω`` radians moves a point of the colliding segment by at most ``ω·lever_j``,
  where ``lever_j`` is the largest distance of such a point from the joint's axis over
  the joint ranges: rotary ``arm``; alpha joint the *true reach* below; beta joint
  ``b`` (the beta arm turns about the elbow).
- **True reach**: the largest distance from the base of any point of the colliding
  segment over the (continuous) joint ranges.  A point at fraction ``s`` of the beta arm
  is at ``|a + s·b·e^{iβ}|`` from the base, convex in ``s``, so the farthest is the
  elbow (``a``) or the fibre; the fibre ``|a + b·e^{iβ}|`` grows with ``cos β``, largest at
  ``lo``, ``hi`` or a multiple of ``2π`` inside ``[lo, hi]``::

      reach = max(a, max_{β ∈ {lo, hi} ∪ 2πℤ∩[lo, hi]} |a + b·e^{iβ}|)

>>> hex_bases(1, 2.0)[:3].round(3).tolist()
[0j, (2+0j), (1+1.732j)]
>>> round(Arm.from_json({"kind": "alpha-beta", "alpha": 10, "beta": 5, "alpha_steps": 4,
...                      "beta_steps": 3, "beta_range": [150, 180]}).reach, 6)   # the elbow
10.0
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .angles import exact_lattice, side_angles, uniform_deg
from .refusal import OracleInputError

__all__ = ["Arm", "OracleInputError", "OracleProblem", "hex_bases"]

#: axial directions of the six edges of a ring, counter-clockwise from the corner on +x
_EDGE_STEPS = ((-1, 1), (-1, 0), (0, -1), (1, -1), (1, 0), (0, 1))
_OMEGA = complex(0.5, math.sqrt(3.0) / 2.0)


def hex_bases(rings: int, pitch: float) -> np.ndarray:
    """The hex layout's bases as a complex array, in ``docs/formats.md`` order (module docstring)."""
    cells = [(0, 0)]
    for r in range(1, int(rings) + 1):
        u, v = r, 0
        for du, dv in _EDGE_STEPS:
            for _ in range(r):
                cells.append((u, v))
                u, v = u + du, v + dv
    axial = np.array(cells, dtype=float)
    return pitch * (axial[:, 0] + axial[:, 1] * _OMEGA)


def _interp_deg(x: np.ndarray, table: tuple[float, ...], wraps: bool) -> np.ndarray:
    """Piecewise-linear angle (degrees) of fractional positions over an own lattice; a
    wrapping joint goes on past its ends (position ``n`` is ``table[0] + 360``)."""
    t = np.asarray(table, dtype=float)
    n = len(t)
    if not wraps:
        return np.interp(x, np.arange(n), t)
    return np.interp(x, np.arange(-1, n + 1), np.concatenate([[t[-1] - 360.0], t, [t[0] + 360.0]]))


@dataclass(frozen=True)
class Arm:
    """One discretised positioner (module docstring): joint ``steps``, ``wraps``, radians
    per step, the angle of index 0, arm ``lengths`` and per-joint ``levers``; ``tables``:
    per joint its own lattice in degrees (``None``: uniform, ``zero + per_step·i``)."""

    kind: str
    lengths: tuple[float, ...]
    steps: tuple[int, ...]
    wraps: tuple[bool, ...]
    per_step: tuple[float, ...]
    zero: tuple[float, ...]
    tables: tuple[tuple[float, ...] | None, ...] | None = None

    @staticmethod
    def from_json(spec: Any) -> Arm:
        if not isinstance(spec, dict):
            raise OracleInputError("kinematics must be an object", value=spec)
        kind = spec.get("kind")
        try:
            if kind == "rotary":
                arm, s = float(spec["arm"]), int(spec["steps"])
                if not (arm > 0 and s >= 2):
                    raise OracleInputError("rotary: arm > 0 and steps >= 2 required", value=spec)
                return Arm("rotary", (arm,), (s,), (True,), (-2 * math.pi / s,), (0.0,))
            if kind == "alpha-beta":
                a, b = float(spec["alpha"]), float(spec["beta"])
                na, nb = int(spec["alpha_steps"]), int(spec["beta_steps"])
                lo, hi = (math.radians(float(x)) for x in spec.get("beta_range", (0.0, 180.0)))
                if not (a > 0 and b > 0 and na >= 2 and nb >= 2 and lo < hi):
                    raise OracleInputError("alpha-beta: positive arms, >= 2 steps, lo < hi required", value=spec)
                if spec.get("alpha_range") is None:
                    return Arm("alpha-beta", (a, b), (na, nb), (True, False),
                               (2 * math.pi / na, (hi - lo) / (nb - 1)), (0.0, lo))
                alo, ahi = (math.radians(float(x)) for x in spec["alpha_range"])
                if not alo < ahi:
                    raise OracleInputError("alpha-beta: alpha_range lo < hi required", value=spec)
                return Arm("alpha-beta", (a, b), (na, nb), (False, False),
                           ((ahi - alo) / (na - 1), (hi - lo) / (nb - 1)), (alo, lo))
        except KeyError as exc:
            raise OracleInputError(f"kinematics.{exc.args[0]} is missing", value=spec) from None
        raise OracleInputError(f"unknown kinematics kind {kind!r}", value=kind)

    def with_tables(self, tables_deg: Sequence[Sequence[float] | None]) -> Arm:
        """The same arm on its own lattice (``tables_deg``: per joint, degrees, or ``None``)."""
        return replace(self, tables=tuple(None if t is None else tuple(float(v) for v in t) for t in tables_deg))

    @property
    def n_joints(self) -> int:
        return len(self.steps)

    @property
    def n_positions(self) -> int:
        return math.prod(self.steps)

    def positions(self) -> np.ndarray:
        """Every position ``(n_positions, J)``; the id of a position is its row (joint 0 slowest)."""
        return np.array(list(itertools.product(*(range(s) for s in self.steps))), dtype=np.int64)

    def position_id(self, q: Sequence[int]) -> int:
        out = 0
        for v, s in zip(q, self.steps):
            out = out * s + int(v)
        return out

    def _table(self, j: int) -> tuple[float, ...] | None:
        return None if self.tables is None else self.tables[j]

    def angles(self, q: np.ndarray) -> list[np.ndarray]:
        """Joint angles (radians) of fractional positions ``q`` ``(..., J)``."""
        q = np.asarray(q, dtype=float)
        out = []
        for j, (z, w) in enumerate(zip(self.zero, self.per_step)):
            t = self._table(j)
            out.append(z + w * q[..., j] if t is None else np.radians(_interp_deg(q[..., j], t, self.wraps[j])))
        return out

    def turn(self, q: np.ndarray, joint: np.ndarray, d: np.ndarray) -> np.ndarray:
        """Signed radians joint ``joint[e]`` turns moving from ``q[e]`` by ``d[e]`` (rows)."""
        q = np.asarray(q, dtype=float)
        joint = np.asarray(joint)
        d = np.asarray(d, dtype=float)
        out = np.array([self.per_step[j] for j in joint], dtype=float) * d
        for j in range(self.n_joints):
            t = self._table(j)
            sel = joint == j
            if t is not None and sel.any():
                x = q[sel, j]
                out[sel] = np.radians(_interp_deg(x + d[sel], t, self.wraps[j]) - _interp_deg(x, t, self.wraps[j]))
        return out

    def max_step(self, j: int) -> float:
        """The largest turn (radians) of one move of joint ``j``."""
        t = self._table(j)
        if t is None:
            return abs(self.per_step[j])
        steps = np.diff(np.asarray(t, dtype=float))
        if self.wraps[j]:
            steps = np.append(steps, t[0] + 360.0 - t[-1])
        return math.radians(float(steps.max()))

    def segment(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The colliding segment's ends ``(p0, p1)`` relative to the base (complex) for ``q`` ``(..., J)``."""
        ang = self.angles(q)
        if self.kind == "rotary":
            tip = self.lengths[0] * np.exp(1j * ang[0])
            return np.zeros_like(tip), tip
        elbow = self.lengths[0] * np.exp(1j * ang[0])
        return elbow, elbow + self.lengths[1] * np.exp(1j * (ang[0] + ang[1]))

    def pivot(self, q: np.ndarray, joint: int) -> np.ndarray:
        """The fixed centre (relative to the base) about which turning ``joint`` turns the
        colliding segment rigidly: the base, or the elbow for the beta joint."""
        p0 = self.segment(q)[0]
        return p0 if (self.kind == "alpha-beta" and joint == 1) else np.zeros_like(p0)

    @property
    def reach(self) -> float:
        """The true reach (module docstring): over the whole beta range, so an own lattice
        (inside that range) does not change it."""
        if self.kind == "rotary":
            return self.lengths[0]
        a, b = self.lengths
        lo, hi = self.zero[1], self.zero[1] + self.per_step[1] * (self.steps[1] - 1)
        turns = range(math.ceil(lo / (2 * math.pi)), math.floor(hi / (2 * math.pi)) + 1)
        candidates = [lo, hi] + [2 * math.pi * k for k in turns]
        return max([a] + [abs(a + b * complex(math.cos(x), math.sin(x))) for x in candidates])

    @property
    def levers(self) -> tuple[float, ...]:
        return (self.lengths[0],) if self.kind == "rotary" else (self.reach, self.lengths[1])

    def speed(self, delta: np.ndarray) -> np.ndarray:
        """Bound on how far any point of the colliding segment moves per unit ``t`` along
        ``q + t·delta`` (``delta`` ``(..., J)``): ``Σ_j |δ_j|·|largest radians per step_j|·lever_j``."""
        delta = np.abs(np.asarray(delta, dtype=float))
        if self.tables is None:
            return sum(delta[..., j] * abs(w) * lev for j, (w, lev) in enumerate(zip(self.per_step, self.levers)))
        return sum(delta[..., j] * self.max_step(j) * lev for j, lev in enumerate(self.levers))

    def successors(self, deltas: np.ndarray) -> np.ndarray:
        """``nxt[u, i]``: the id after position ``i`` moves every joint by ``deltas[u]``
        (wrapping joints wrap), ``−1`` past a hard stop."""
        pos = self.positions()
        out = np.full((len(deltas), len(pos)), -1, dtype=np.int64)
        steps = np.array(self.steps)
        for u, d in enumerate(np.asarray(deltas, dtype=np.int64).reshape(len(deltas), -1)):
            q = pos + d
            ok = np.ones(len(pos), dtype=bool)
            for j, w in enumerate(self.wraps):
                if w:
                    q[:, j] %= steps[j]
                else:
                    ok &= (q[:, j] >= 0) & (q[:, j] < steps[j])
            ids = np.zeros(len(pos), dtype=np.int64)
            for j in range(self.n_joints):
                ids = ids * steps[j] + q[:, j]
            out[u, ok] = ids[ok]
        return out


@dataclass
class OracleProblem:
    """Bases (complex), the arm, buffers, start and target position ids, from PROBLEM.json;
    ``arms``: each robot's own arm (its own lattice) where the problem gives angles
    (``None``: every robot is ``arm``); ``margin``: clearance on top of the buffers (mm)."""

    bases: np.ndarray
    arm: Arm
    buffers: np.ndarray
    start: list[int]
    target: list[int]
    arms: list[Arm] | None = None
    margin: float = 0.0
    #: per robot the exact (α, β) of its start and target (degrees), with own lattices
    angles: tuple[list[tuple[float, float]], list[tuple[float, float]]] | None = None

    @property
    def n(self) -> int:
        return len(self.bases)

    def arm_of(self, p: int) -> Arm:
        return self.arm if self.arms is None else self.arms[p]

    def need(self, a: int, b: int) -> float:
        """The least distance robots ``a`` and ``b`` must keep: ``r_a + r_b + margin``."""
        return float(self.buffers[a] + self.buffers[b]) + self.margin

    @staticmethod
    def from_json(data: Any) -> OracleProblem:
        if not isinstance(data, dict):
            raise OracleInputError("a problem must be a JSON object", value=data)
        try:
            layout, kin, buf = data["layout"], data["kinematics"], data["collision"]["buffer"]
            start, target = data["start"], data["target"]
        except (KeyError, TypeError) as exc:
            raise OracleInputError(f"field {exc} is missing (the oracle reads Problem.to_json())", value=None) from None
        margin = float(data["collision"].get("margin", 0.0))
        if not margin >= 0:
            raise OracleInputError(f"collision.margin must be >= 0, got {margin}", value=margin)
        if layout.get("kind") == "hex":
            bases = hex_bases(int(layout["rings"]), float(layout["pitch"]))
        elif layout.get("kind") == "points":
            xy = np.asarray(layout["xy"], dtype=float).reshape(-1, 2)
            bases = xy[:, 0] + 1j * xy[:, 1]
        else:
            raise OracleInputError(f"unknown layout kind {layout.get('kind')!r}", value=layout)
        arm = Arm.from_json(kin)
        n = len(bases)
        buffers = np.broadcast_to(np.asarray(buf, dtype=float), (n,)).copy()
        if isinstance(start, dict) or isinstance(target, dict):
            return OracleProblem._with_lattices(bases, arm, kin, buffers, margin, start, target)
        ids = []
        for name, conf in (("start", start), ("target", target)):
            ids.append(index_ids(arm, name, conf, n))
        return OracleProblem(bases, arm, buffers, ids[0], ids[1], margin=margin)


    @staticmethod
    def _with_lattices(bases: np.ndarray, arm: Arm, kin: dict, buffers: np.ndarray, margin: float, start: Any,
                       target: Any) -> OracleProblem:
        """Every robot on its own lattice holding its exact start and target angles (:mod:`.angles`)."""
        if arm.kind != "alpha-beta":
            raise OracleInputError("angles need alpha-beta kinematics", value=arm.kind)
        n = len(bases)
        arange = kin.get("alpha_range")
        alo, ahi = (0.0, 360.0) if arange is None else (float(arange[0]), float(arange[1]))
        blo, bhi = (float(x) for x in kin.get("beta_range", (0.0, 180.0)))
        grids = (uniform_deg(arm.steps[0], arm.wraps[0], alo, ahi), uniform_deg(arm.steps[1], False, blo, bhi))
        ends = []
        for name, conf in (("start", start), ("target", target)):
            if isinstance(conf, dict):
                ends.append(side_angles(name, conf, kin, arm.lengths, bases))
            else:  # indices: the uniform positions
                ends.append([(float(grids[0][i // arm.steps[1]]), float(grids[1][i % arm.steps[1]]))
                             for i in index_ids(arm, name, conf, n)])
        arms, ids = [], ([], [])
        shared: dict[Arm, Arm] = {}
        for p in range(n):
            (sa, sb), (ta, tb) = ends[0][p], ends[1][p]
            tab_a, (ia_s, ia_t) = exact_lattice(grids[0], [sa, ta], arm.wraps[0])
            tab_b, (ib_s, ib_t) = exact_lattice(grids[1], [sb, tb], False)
            own = arm.with_tables((tab_a, tab_b))
            arms.append(shared.setdefault(own, own))
            ids[0].append(ia_s * arm.steps[1] + ib_s)
            ids[1].append(ia_t * arm.steps[1] + ib_t)
        return OracleProblem(bases, arm, buffers, ids[0], ids[1], arms=arms, margin=margin, angles=(ends[0], ends[1]))


def index_ids(arm: Arm, name: str, conf: Any, n: int) -> list[int]:
    if not isinstance(conf, list):
        raise OracleInputError(f"{name} must be a list of positions or an object with angles", value=conf)
    if len(conf) != n:
        raise OracleInputError(f"{name} has {len(conf)} positions for {n} positioners", value=conf)
    row = []
    for q in conf:
        q = [q] if arm.kind == "rotary" else list(q)
        if len(q) != arm.n_joints or not all(0 <= int(v) < s for v, s in zip(q, arm.steps)):
            raise OracleInputError(f"{name}: position {q} out of range", value=q)
        row.append(arm.position_id(q))
    return row
