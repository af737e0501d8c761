"""The validator's geometry: robots at joint angles, segment distances, the certified check of a motion.

:mod:`.validate` reads a plan into a motion; this module says where that motion collides
(:class:`MotionChecker`, the rule in :mod:`.validate`'s docstring).  A step is a motion **linear in joint angle**, ``θ(t) = θ_0 + t·Δθ`` (``t ∈ [0, 1]``, all joints
of all robots together); robot ``p``'s colliding segment at any angles is its kinematics'
two-link chain (:meth:`~supcoord.geometry.joint_space.Kinematics.chain`, the formula of its
``segments_at_deg``, evaluated for all robots at once by :func:`supcoord.geometry.chain.chain_segments`)
placed at its base (each robot its own geometry), fixed obstacles are segments with buffers.
Of :mod:`supcoord.geometry` the validator uses only that (and :meth:`Problem.angles_deg`), never the collision tables or their sweeps: segment distances
are Ericson's clamped closest points, neighbours come from its own bound, and each step is
sampled, then bisected with the pair's Lipschitz bound: every point of robot ``p``'s segment
moves at most ``L_p = reach_p·|Δα| + ρ_p·|Δβ|`` (radians; ``reach_p`` the kinematics' reach,
``ρ_p`` the farthest point of the segment from the elbow; rotary ``arm·|Δθ|``), so a pair's
distance is ``(L_a + L_b)``-Lipschitz in ``t``.

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.9.
- P. Hansen, B. Jaumard, S.-H. Lu, Global optimization of univariate Lipschitz functions,
  Mathematical Programming 55, 1992.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..geometry.chain import chain_angles_deg, chain_segments
from ..geometry.fleet import chain_arrays

__all__ = ["segment_distance_ericson", "step_distances", "Bodies", "MotionCheck", "MotionChecker", "TOLERANCE",
           "MAX_OPEN", "MAX_TURNS", "TIE"]

#: depth (mm) below which bisection stops: a collision shallower than this can pass unseen
TOLERANCE = 1e-6
#: intervals bisected at once (bounds the memory of one round)
_ROWS = 200_000
#: open intervals of one pair and step beyond which bisection stops: the pair touches along
#: a stretch (distance exactly ``r_a + r_b``), which no sampling can settle; the result
#: reports how deep a collision there could be (``undecided_depth``)
MAX_OPEN = 64
#: most full turns of a joint in one step that the geometric check follows (beyond: reported)
MAX_TURNS = 100
#: depth (mm) of an overlap the validator attributes to rounding: arms that touch at exactly the
#: buffer sum (round-number layouts) come out 1e-15 mm either side of it in double precision,
#: differently in the planner's formulas and in these, so a touch is not reported as a collision
TIE = 1e-9


def segment_distance_ericson(p1: Any, q1: Any, p2: Any, q2: Any) -> np.ndarray:
    """Distance between segments ``[p1, q1]`` and ``[p2, q2]`` via clamped closest parameters.

    Every candidate is the distance between two actual points of the segments, so the
    result is never below the true distance; the end-point candidates make it exact
    also for nearly parallel segments that do not meet, and an orientation test gives 0
    for segments that cross (at a small angle the parametric candidate is off by the
    cancellation in ``a·e − b²``).

    >>> float(segment_distance_ericson([0, 1e-6], [2, 0], [3, 1e-6], [0, 0]))   # crossing at x = 1.2
    0.0

    >>> round(float(segment_distance_ericson([0, 0], [2, 0], [3, 1], [5, 1])) ** 2, 12)
    2.0
    """
    p1, q1, p2, q2 = (np.asarray(v, float) for v in (p1, q1, p2, q2))
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f, c, b = _dot(d1, d1), _dot(d2, d2), _dot(d2, r), _dot(d1, r), _dot(d1, d2)
    tiny = 1e-300
    denom = a * e - b * b
    # s on segment 1 from the infinite lines' closest points, clamped (0 when parallel)
    s = np.where(denom > 1e-12 * np.maximum(a * e, tiny), np.clip((b * f - c * e) / np.where(denom > 0, denom, 1), 0, 1), 0.0)
    s = np.where(a <= tiny, 0.0, s)
    t = np.where(e > tiny, (b * s + f) / np.where(e > tiny, e, 1), 0.0)
    # t outside [0, 1]: clamp it and recompute s for the clamped t
    t_lo, t_hi = (t < 0) | (e <= tiny), t > 1  # a point-like segment 2: t = 0, s from it
    t = np.clip(t, 0, 1)
    s_lo = np.where(a > tiny, np.clip(-c / np.where(a > tiny, a, 1), 0, 1), 0.0)
    s_hi = np.where(a > tiny, np.clip((b - c) / np.where(a > tiny, a, 1), 0, 1), 0.0)
    s = np.where(t_lo, s_lo, np.where(t_hi, s_hi, s))
    c1 = p1 + s[..., None] * d1
    c2 = p2 + t[..., None] * d2
    d = np.sqrt(_dot(c1 - c2, c1 - c2))
    # nearly parallel segments (the cancellation in a·e − b²) can leave s off its optimum;
    # the distance is then attained at an end point, so the four end-point distances repair it
    ends = [_to_segment(p1, p2, d2, e), _to_segment(q1, p2, d2, e), _to_segment(p2, p1, d1, a), _to_segment(q2, p1, d1, a)]
    d = np.minimum(d, np.minimum(np.minimum(ends[0], ends[1]), np.minimum(ends[2], ends[3])))
    # a proper crossing: each segment's end points on opposite sides of the other's line
    o1, o2 = _cross(d1, p2 - p1), _cross(d1, q2 - p1)
    o3, o4 = _cross(d2, p1 - p2), _cross(d2, q1 - p2)
    crossing = (o1 * o2 < 0) & (o3 * o4 < 0)
    return np.where(crossing, 0.0, d)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _to_segment(x: np.ndarray, start: np.ndarray, direction: np.ndarray, length2: np.ndarray) -> np.ndarray:
    u = _dot(x - start, direction) / np.where(length2 > 0, length2, 1.0)
    u = np.clip(u, 0.0, 1.0)
    w = start + u[..., None] * direction - x
    return np.sqrt(_dot(w, w))


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]


def _segment_radius(kin: Any) -> float:
    """Farthest point of the colliding segment from the last joint's axis (0 for one joint):
    for alpha-beta the elbow, at ``(alpha, 0)`` when both angles are 0."""
    if kin.n_joints == 1:
        return 0.0
    seg = np.asarray(kin.segments_at_deg(np.zeros(kin.n_joints)), float)
    return float(np.hypot(seg[:, 0] - kin.alpha, seg[:, 1]).max())


class Bodies:
    """Robots and fixed obstacles as the validator sees them: entities ``0 … N−1`` are robots
    (base, own kinematics, Lipschitz radii), ``N … N+M−1`` the obstacles (fixed segments)."""

    def __init__(self, problem: Any, bases: np.ndarray):
        n = problem.n
        self.n, self.bases = n, np.asarray(bases, float)
        self.kins: list[Any] = []
        keys: dict[Any, int] = {}
        group = np.zeros(n, dtype=int)
        for p in range(n):
            kin = problem.kin(p)
            key = kin.key() if problem.robot_kinematics is not None else 0
            if key not in keys:
                keys[key] = len(self.kins)
                self.kins.append(kin)
            group[p] = keys[key]
        self.reach = np.array([self.kins[g].reach for g in group], float).reshape(n)
        # each robot's arms (the kinematics' chain), to place robots with their own arms at once
        self.l1, self.seg, self.offsets = chain_arrays([self.kins[g] for g in group])
        radius = [_segment_radius(k) for k in self.kins]
        self.radius = np.array([radius[g] for g in group], float).reshape(n)
        self.obstacles = np.asarray(getattr(problem, "obstacles", np.zeros((0, 2, 2))), float).reshape(-1, 2, 2)
        self.m = len(self.obstacles)
        obuf = np.asarray(getattr(problem, "obstacle_buffers", np.zeros(0)), float).reshape(self.m)
        self.buffers = np.concatenate([np.asarray(problem.buffers, float), obuf])
        self.group = np.concatenate([group, np.full(self.m, -1)])

    def pad(self, angles: np.ndarray) -> np.ndarray:
        """Robots' angles ``(N, J)`` with zero rows for the obstacles."""
        return np.concatenate([angles, np.zeros((self.m, angles.shape[1]))])

    def travel(self, turn_deg: np.ndarray) -> np.ndarray:
        """Per entity, how far any point of it moves over a step turning the joints by
        ``turn_deg`` ``(N+M, J)``: ``reach·|Δθ_0| + ρ·|Δθ_1|`` (radians), 0 for obstacles."""
        turn = np.radians(np.abs(turn_deg[: self.n]))
        out = self.reach * turn[:, 0]
        if turn.shape[1] > 1:
            out = out + self.radius * turn[:, 1:].sum(axis=1)
        return np.concatenate([out, np.zeros(self.m)])

    def pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """``(ia, ib)``: robot pairs ``a < b`` whose bases are closer than ``reach_a + reach_b +
        2·max r`` (farther ones never meet), then robot–obstacle pairs ``(p, N + o)`` closer than
        ``reach_p + r_p + r_o``."""
        n, buf = self.n, self.buffers
        rmax = float(self.reach.max(initial=0.0))
        ia, ib = _close_pairs(self.bases, 2 * rmax + 2 * buf[:n].max(initial=0.0))
        near = np.hypot(*(self.bases[ia] - self.bases[ib]).T) < self.reach[ia] + self.reach[ib] + 2 * buf[:n].max(initial=0.0)
        ia, ib = ia[near], ib[near]
        if self.m and n:
            o = self.obstacles
            d = _to_segment(self.bases[:, None, :], o[None, :, 0], o[None, :, 1] - o[None, :, 0],
                            _dot(o[:, 1] - o[:, 0], o[:, 1] - o[:, 0])[None, :])
            pa, po = np.nonzero(d < self.reach[:, None] + buf[:n, None] + buf[None, n:])
            ia, ib = np.concatenate([ia, pa]), np.concatenate([ib, n + po])
        return ia, ib

    def segments(self, e: np.ndarray, angles: np.ndarray) -> np.ndarray:
        """Absolute segments ``(K, S, 2, 2)`` of entities ``e`` ``(K,)`` at angles ``(K, S, J)``."""
        g = self.group[e]
        if len(self.kins) == 1 and not self.m:
            return self.kins[0].segments_at_deg(angles) + self.bases[e][:, None, None, :]
        out = np.empty(angles.shape[:-1] + (2, 2))
        rob = np.nonzero(g >= 0)[0]
        if len(rob):
            r = e[rob]
            a, b = chain_angles_deg(angles[rob], self.offsets[r][:, None, :])
            out[rob] = chain_segments(self.l1[r][:, None], self.seg[r][:, None], a, b) + self.bases[r][:, None, None, :]
        obs = g < 0
        if obs.any():
            out[obs] = self.obstacles[e[obs] - self.n][:, None, :, :]
        return out


def step_distances(bodies: Bodies, a0: np.ndarray, turn: np.ndarray, ia: np.ndarray, ib: np.ndarray,
                    travel: np.ndarray, need: np.ndarray,
                    resolution: float) -> tuple[np.ndarray, np.ndarray, tuple[int, float]]:
    """Least distance of each pair ``(ia, ib)`` over the step ``a0 + t·turn`` (angles of the
    entities, :class:`Bodies`), the ``t`` where it occurs (0 when the start is closest) and
    ``(pairs left open, the deepest collision they could hide)``: sampled so that no point
    moves more than ``resolution/2`` between samples, then bisected where the samples do not
    settle ``d ≥ need`` (module docstring).  A pair whose end points already settle it by the
    Lipschitz bound is not sampled (its least distance is then reported from the end points)."""
    moving = np.any(turn != 0, axis=1)
    sel = np.nonzero(moving[ia] | moving[ib])[0]
    d_static = _distances_at(bodies, a0, turn, ia, ib, np.zeros((len(ia), 1)))[:, 0]
    dmin, tmin = d_static.copy(), np.zeros(len(ia))
    if not len(sel):
        return dmin, tmin, (0, 0.0)
    # end points first: d(t) is L-Lipschitz, so (d(0) + d(1) − L)/2 ≥ need clears a pair at once
    d_end = _distances_at(bodies, a0, turn, ia[sel], ib[sel], np.ones((len(sel), 1)))[:, 0]
    lip = travel[ia[sel]] + travel[ib[sel]]
    clear = (d_static[sel] + d_end - lip) / 2 >= need[sel]
    at_end = d_end < dmin[sel]
    dmin[sel[clear & at_end]] = d_end[clear & at_end]
    tmin[sel[clear & at_end]] = 1.0
    sel = sel[~clear]
    if not len(sel):
        return dmin, tmin, (0, 0.0)
    lip = travel[ia[sel]] + travel[ib[sel]]  # d(t) is L-Lipschitz for the pair
    samples = max(1, math.ceil(2 * float(np.maximum(travel[ia[sel]], travel[ib[sel]]).max()) / resolution))
    t = np.linspace(0.0, 1.0, samples + 1)
    rows: list[np.ndarray] = []  # undecided intervals: (pair, t0, t1, d0, d1)
    per = max(1, _ROWS // len(t))
    for lo in range(0, len(sel), per):
        idx = np.arange(lo, min(lo + per, len(sel)))
        dist = _distances_at(bodies, a0, turn, ia[sel[idx]], ib[sel[idx]], np.broadcast_to(t, (len(idx), len(t))))
        best = dist.argmin(axis=1)
        dmin[sel[idx]] = dist[np.arange(len(idx)), best]
        tmin[sel[idx]] = t[best]
        bound = (dist[:, :-1] + dist[:, 1:] - lip[idx, None] / samples) / 2
        open_ = (bound < need[sel[idx], None]) & (dmin[sel[idx], None] >= need[sel[idx], None])
        pi, ti = np.nonzero(open_)
        if len(pi):
            rows.append(np.stack([idx[pi], t[ti], t[ti + 1], dist[pi, ti], dist[pi, ti + 1]], axis=1))
    depth = np.zeros(len(sel))  # per pair: how deep a collision the bisection could not exclude
    work = np.concatenate(rows) if rows else np.zeros((0, 5))
    while len(work):
        j = work[:, 0].astype(int)
        counts = np.bincount(j, minlength=len(sel))
        crowded = counts[j] > MAX_OPEN  # a contact along a whole stretch (d = r_a + r_b): stop there
        if crowded.any():
            gap = need[sel[j]] - (work[:, 3] + work[:, 4] - lip[j] * (work[:, 2] - work[:, 1])) / 2
            np.maximum.at(depth, j[crowded], gap[crowded])
            work = work[~crowded]
            continue
        batch, work = work[:_ROWS], work[_ROWS:]
        j = batch[:, 0].astype(int)
        mid = (batch[:, 1] + batch[:, 2]) / 2
        dm = _distances_at(bodies, a0, turn, ia[sel[j]], ib[sel[j]], mid[:, None])[:, 0]
        better = dm < dmin[sel[j]]
        np.minimum.at(dmin, sel[j], dm)
        tmin[sel[j[better]]] = mid[better]
        halves = np.concatenate([np.stack([j, batch[:, 1], mid, batch[:, 3], dm], axis=1),
                                 np.stack([j, mid, batch[:, 2], dm, batch[:, 4]], axis=1)])
        k = halves[:, 0].astype(int)
        width = halves[:, 2] - halves[:, 1]
        bound = (halves[:, 3] + halves[:, 4] - lip[k] * width) / 2
        alive = (bound < need[sel[k]]) & (dmin[sel[k]] >= need[sel[k]])  # a collision found ends the pair
        settled = alive & (lip[k] * width / 2 <= TOLERANCE)
        np.maximum.at(depth, k[settled], need[sel[k[settled]]] - bound[settled])
        work = np.concatenate([work, halves[alive & ~settled]])
    open_pairs = (depth > 0) & (dmin[sel] >= need[sel])
    return dmin, tmin, (int(open_pairs.sum()), float(depth[open_pairs].max(initial=0.0)))


def _distances_at(bodies: Bodies, a0: np.ndarray, turn: np.ndarray, a: np.ndarray, b: np.ndarray,
                  t: np.ndarray) -> np.ndarray:
    """Distances of the pairs ``(a[i], b[i])`` at the times ``t[i, :]`` of the step ``a0 + t·turn``."""
    qa = a0[a][:, None, :] + t[:, :, None] * turn[a][:, None, :]
    qb = a0[b][:, None, :] + t[:, :, None] * turn[b][:, None, :]
    sa, sb = bodies.segments(a, qa), bodies.segments(b, qb)
    return segment_distance_ericson(sa[..., 0, :], sa[..., 1, :], sb[..., 0, :], sb[..., 1, :])


def _close_pairs(bases: np.ndarray, limit: float) -> tuple[np.ndarray, np.ndarray]:
    """All ``(a, b)``, ``a < b``, with bases closer than ``limit`` (row blocks, no N² memory)."""
    out_a, out_b = [], []
    rows = max(1, 4_000_000 // max(len(bases), 1))
    for lo in range(0, len(bases), rows):
        d = np.hypot(*(bases[lo:lo + rows, None, :] - bases[None, :, :]).transpose(2, 0, 1))
        a, b = np.nonzero(d < limit)
        a = a + lo
        out_a.append(a[a < b])
        out_b.append(b[a < b])
    return np.concatenate(out_a), np.concatenate(out_b)


@dataclass(frozen=True)
class MotionCheck:
    """What the geometric check of a motion found: colliding (step, pair) incidents, the
    least clearance ``dist − (r_a + r_b)`` (mm, ``inf`` when no pair was checked), the first
    incidents (``{"step", "positioners", "t", "distance", "required"[, "obstacle"]}``), the
    pairs left undecided and how deep a collision they could hide (mm)."""

    collisions: int = 0
    clearance: float = math.inf
    incidents: list[dict[str, Any]] = field(default_factory=list)
    undecided: int = 0
    depth: float = 0.0

    def plus(self, other: MotionCheck) -> MotionCheck:
        """Both checks' findings (the incidents listed are this check's)."""
        return MotionCheck(self.collisions + other.collisions, min(self.clearance, other.clearance), self.incidents,
                           self.undecided + other.undecided, max(self.depth, other.depth))


class MotionChecker:
    """The certified collision check of motions among ``problem``'s robots on ``bases``: the
    pairs that can meet (:meth:`Bodies.pairs`), each needing ``dist ≥ r_a + r_b``, sampled at
    ``resolution`` (mm) then bisected (:func:`step_distances`); at most ``max_incidents``
    incidents are listed."""

    def __init__(self, problem: Any, bases: np.ndarray, resolution: float, max_incidents: int):
        self.bodies = Bodies(problem, bases)
        self.ia, self.ib = self.bodies.pairs()
        self.need = self.bodies.buffers[self.ia] + self.bodies.buffers[self.ib]
        self.resolution, self.max_incidents = resolution, max_incidents

    def check(self, step: Callable[[int], tuple[np.ndarray, np.ndarray]], count: int, single: str,
              problems: list[str]) -> MotionCheck:
        """Check ``count`` poses, ``step(k)`` giving pose ``k``'s angles ``(N, J)`` (degrees) and
        the turn to pose ``k + 1``; each collision is appended to ``problems`` (a one-pose
        motion is named ``single``)."""
        bodies, ia, ib, need = self.bodies, self.ia, self.ib, self.need
        n = bodies.n
        collisions = undecided = 0
        depth = 0.0
        clearance = math.inf
        incidents: list[dict[str, Any]] = []
        for k in range(max(1, count - 1)):
            a0, turn = step(k)
            a0, turn = bodies.pad(a0), bodies.pad(turn)
            where = f"step {k}->{k + 1}" if count > 1 else single
            # a step turning a joint by more than a turn is checked a turn at a time (the same motion)
            pieces = max(1, math.ceil(float(np.abs(turn).max(initial=0.0)) / 360.0))
            if pieces > MAX_TURNS:
                problems.append(f"{where}: a joint turns by {float(np.abs(turn).max()):.6g} deg, more than {MAX_TURNS} "
                                f"turns: not checked for collisions")
                continue
            dmin, tmin = np.full(len(ia), np.inf), np.zeros(len(ia))
            for i in range(pieces):
                part = turn / pieces
                d, t, (unsure, deep) = step_distances(bodies, a0 + i * part, part, ia, ib, bodies.travel(part),
                                                      need - TIE, self.resolution)
                tmin = np.where(d < dmin, (i + t) / pieces, tmin)
                dmin = np.minimum(dmin, d)
                undecided += unsure
                depth = max(depth, deep)
            if len(dmin):
                clearance = min(clearance, float(np.min(dmin - need)))
            hits = np.nonzero(dmin < need - TIE)[0]
            collisions += len(hits)
            for h in hits:
                a, b = int(ia[h]), int(ib[h])
                what = f"positioners {a} and {b} collide" if b < n else f"positioner {a} collides with obstacle {b - n}"
                problems.append(f"{where}: {what} (distance {dmin[h]:.3f} mm < {need[h]:.3f} mm)")
                if len(incidents) < self.max_incidents:
                    inc = {"step": k, "positioners": [a, b] if b < n else [a], "t": float(tmin[h]),
                           "distance": float(dmin[h]), "required": float(need[h])}
                    if b >= n:
                        inc["obstacle"] = b - n
                    incidents.append(inc)
        return MotionCheck(collisions, clearance, incidents, undecided, depth)
