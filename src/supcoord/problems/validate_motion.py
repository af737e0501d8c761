"""The validator's geometry: robots at joint angles, segment distances, the certified check of a motion.

:mod:`.validate` reads a plan into a motion; this module says where that motion collides
(:class:`MotionChecker`, the rule in :mod:`.validate`'s docstring).  A step is a motion **linear
in joint angle**, ``θ(t) = θ_0 + t·Δθ`` (``t ∈ [0, 1]``, all joints of all robots together).

Everything geometric here is the validator's own, written apart from :mod:`supcoord.geometry`
(which it does not import): robot ``p``'s colliding segment at any angles is a planar two-link
chain read from its kinematics' numbers (first link ``l1``, the segment in the second link's
frame, the joints' calibration offsets) and placed at its base — the elbow at
``l1·(cos a, sin a)``, the end points ``elbow + R(a + b)·s_k`` — and each fixed obstacle is a
chain without links whose segment never moves.  Segment distances are Ericson's clamped
closest points; neighbours come from the validator's own bound; and each step is sampled, then
bisected with the pair's Lipschitz bound: every point of robot ``p``'s segment moves at most
``L_p = reach_p·|Δα| + ρ_p·|Δβ|`` (radians; ``reach_p`` the kinematics' reach, ``ρ_p`` the
farthest point of the segment from the elbow; rotary ``arm·|Δθ|``), so a pair's distance is
``(L_a + L_b)``-Lipschitz in ``t``.

The work is done on arrays over every (step, pair) entry of a block of steps at once
(:func:`pieces_distances`): the poses at the start and the end of every step, the samples
of every step that its end points leave open, and each round of the bisection of all of
them, so a plan of many steps costs a few dozen numpy calls per block, not per step.

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

from .validation_result import Incident

__all__ = ["segment_distance_ericson", "pieces_distances", "Bodies", "MotionCheck", "MotionChecker", "TOLERANCE",
           "MAX_OPEN", "MAX_TURNS", "TIE"]

#: depth (mm) below which bisection stops: a collision shallower than this can pass unseen
TOLERANCE = 1e-6
#: distances computed per numpy call: the temporaries then stay in the processor's cache
#: (about 2.5 times faster per distance than one call over 250,000 pairs)
_ROWS = 16_384
#: (step, pair) entries checked together: steps are gathered into blocks of about this many
_ENTRIES = 250_000
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

    Parameters
    ----------
    p1, q1, p2, q2 : array_like, shape (..., 2)
        End points (mm) of the two segments; the leading axes broadcast.

    Returns
    -------
    numpy.ndarray
        The distances (mm), of the broadcast leading shape.

    Examples
    --------
    >>> float(segment_distance_ericson([0, 1e-6], [2, 0], [3, 1e-6], [0, 0]))   # crossing at x = 1.2
    0.0

    >>> round(float(segment_distance_ericson([0, 0], [2, 0], [3, 1], [5, 1])) ** 2, 12)
    2.0
    """
    p1, q1, p2, q2 = (np.asarray(v, float) for v in (p1, q1, p2, q2))
    return _ericson(p1[..., 0], p1[..., 1], q1[..., 0], q1[..., 1], p2[..., 0], p2[..., 1], q2[..., 0], q2[..., 1])


def _ericson(p1x: Any, p1y: Any, q1x: Any, q1y: Any, p2x: Any, p2y: Any, q2x: Any, q2y: Any) -> np.ndarray:
    """:func:`segment_distance_ericson` on coordinate arrays (broadcast)."""
    d1x, d1y, d2x, d2y = q1x - p1x, q1y - p1y, q2x - p2x, q2y - p2y
    rx, ry = p1x - p2x, p1y - p2y
    a, e, b = d1x * d1x + d1y * d1y, d2x * d2x + d2y * d2y, d1x * d2x + d1y * d2y
    f, c = d2x * rx + d2y * ry, d1x * rx + d1y * ry
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
    wx, wy = (p1x + s * d1x) - (p2x + t * d2x), (p1y + s * d1y) - (p2y + t * d2y)
    d = np.sqrt(wx * wx + wy * wy)
    # nearly parallel segments (the cancellation in a·e − b²) can leave s off its optimum;
    # the distance is then attained at an end point, so the four end-point distances repair it
    d = np.minimum(d, np.minimum(np.minimum(_to_segment(p1x, p1y, p2x, p2y, d2x, d2y, e),
                                            _to_segment(q1x, q1y, p2x, p2y, d2x, d2y, e)),
                                 np.minimum(_to_segment(p2x, p2y, p1x, p1y, d1x, d1y, a),
                                            _to_segment(q2x, q2y, p1x, p1y, d1x, d1y, a))))
    # a proper crossing: each segment's end points on opposite sides of the other's line
    o1 = d1x * (p2y - p1y) - d1y * (p2x - p1x)
    o2 = d1x * (q2y - p1y) - d1y * (q2x - p1x)
    o3 = d2x * (p1y - p2y) - d2y * (p1x - p2x)
    o4 = d2x * (q1y - p2y) - d2y * (q1x - p2x)
    crossing = (o1 * o2 < 0) & (o3 * o4 < 0)
    return np.where(crossing, 0.0, d)


def _to_segment(xx: Any, xy: Any, sx: Any, sy: Any, dx: Any, dy: Any, length2: Any) -> np.ndarray:
    """Distance from the point ``x`` to the segment from ``s`` along ``d`` (``length2 = |d|²``)."""
    u = ((xx - sx) * dx + (xy - sy) * dy) / np.where(length2 > 0, length2, 1.0)
    u = np.clip(u, 0.0, 1.0)
    wx, wy = (sx + u * dx) - xx, (sy + u * dy) - xy
    return np.sqrt(wx * wx + wy * wy)


def _segment_radius(seg: np.ndarray, joints: int) -> float:
    """Farthest point of the colliding segment from the last joint's axis (0 for one joint): the
    elbow is the origin of the second link's frame, in which ``seg`` ``(2, 2)`` is given, so
    whatever the angles and calibration offsets it is the farther end point's norm."""
    if joints == 1:
        return 0.0
    return float(np.hypot(seg[:, 0], seg[:, 1]).max())


def _chain(l1: Any, seg: np.ndarray, a: Any, b: Any) -> tuple[np.ndarray, ...]:
    """End points ``(x0, y0, x1, y1)`` relative to the base of chains with first links ``l1``
    and segments ``seg`` ``(..., 2, 2)`` (second link's frame) at angles ``a``, ``b`` (radians)."""
    ex, ey = l1 * np.cos(a), l1 * np.sin(a)
    c, sn = np.cos(a + b), np.sin(a + b)
    return (ex + (seg[..., 0, 0] * c - seg[..., 0, 1] * sn), ey + (seg[..., 0, 0] * sn + seg[..., 0, 1] * c),
            ex + (seg[..., 1, 0] * c - seg[..., 1, 1] * sn), ey + (seg[..., 1, 0] * sn + seg[..., 1, 1] * c))


class Bodies:
    """Robots and fixed obstacles as the validator sees them: entities ``0 … N−1`` are robots
    (base, own arms, Lipschitz radii), ``N … N+M−1`` the obstacles (fixed segments, base 0).
    Every entity is a chain (module docstring): ``base``, ``l1``, ``seg`` and ``offsets`` hold
    each one's numbers, an obstacle's with no link and its segment where it stands."""

    def __init__(self, problem: Any, bases: np.ndarray):
        n = problem.n
        self.n = n
        kins: list[Any] = []
        keys: dict[Any, int] = {}
        group = np.zeros(n, dtype=int)
        for p in range(n):
            kin = problem.kin(p)
            key = kin.key() if problem.robot_kinematics is not None else 0
            if key not in keys:
                keys[key] = len(kins)
                kins.append(kin)
            group[p] = keys[key]
        chains = [k.chain() for k in kins]
        l1 = np.array([c[0] for c in chains], float)
        seg = np.array([c[1] for c in chains], float).reshape(len(kins), 2, 2)
        offsets = np.array([k.chain_offsets_deg() for k in kins], float).reshape(len(kins), -1)
        self.joints = offsets.shape[1] if len(kins) else problem.kinematics.n_joints
        self.reach = np.array([kins[g].reach for g in group], float).reshape(n)
        radius = [_segment_radius(seg[g], self.joints) for g in range(len(kins))]
        self.radius = np.array([radius[g] for g in group], float).reshape(n)
        self.obstacles = np.asarray(getattr(problem, "obstacles", np.zeros((0, 2, 2))), float).reshape(-1, 2, 2)
        self.m = m = len(self.obstacles)
        obuf = np.asarray(getattr(problem, "obstacle_buffers", np.zeros(0)), float).reshape(m)
        self.buffers = np.concatenate([np.asarray(problem.buffers, float), obuf])
        self.bases = np.asarray(bases, float).reshape(n, 2)
        self.base = np.concatenate([self.bases, np.zeros((m, 2))])
        self.l1 = np.concatenate([l1[group], np.zeros(m)])
        self.seg = np.concatenate([seg[group], self.obstacles])
        self.offsets = np.concatenate([offsets[group], np.zeros((m, self.joints))])

    def pad(self, angles: np.ndarray) -> np.ndarray:
        """Robots' angles ``(N, J)`` with zero rows for the obstacles."""
        return np.concatenate([angles, np.zeros((self.m, angles.shape[1]))])

    def travel(self, turn_deg: np.ndarray) -> np.ndarray:
        """Per entity, how far any point of it moves over a step turning the joints by
        ``turn_deg`` ``(..., N+M, J)``: ``reach·|Δθ_0| + ρ·|Δθ_1|`` (radians), 0 for obstacles."""
        turn = np.radians(np.abs(turn_deg[..., : self.n, :]))
        out = self.reach * turn[..., 0]
        if turn.shape[-1] > 1:
            out = out + self.radius * turn[..., 1:].sum(axis=-1)
        return np.concatenate([out, np.zeros(out.shape[:-1] + (self.m,))], axis=-1)

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
            ux, uy = o[None, :, 1, 0] - o[None, :, 0, 0], o[None, :, 1, 1] - o[None, :, 0, 1]
            d = _to_segment(self.bases[:, None, 0], self.bases[:, None, 1], o[None, :, 0, 0], o[None, :, 0, 1],
                            ux, uy, ux * ux + uy * uy)
            pa, po = np.nonzero(d < self.reach[:, None] + buf[:n, None] + buf[None, n:])
            ia, ib = np.concatenate([ia, pa]), np.concatenate([ib, n + po])
        return ia, ib

    def place(self, e: np.ndarray, angles: np.ndarray) -> tuple[np.ndarray, ...]:
        """Placed segments ``(x0, y0, x1, y1)`` of entities ``e`` at joint angles ``angles``
        ``(..., J)`` (degrees; ``e`` broadcasts against ``angles``' leading axes)."""
        rad = np.radians(angles + self.offsets[e])
        a = rad[..., 0] if rad.shape[-1] > 1 else np.zeros(rad.shape[:-1])
        x0, y0, x1, y1 = _chain(self.l1[e], self.seg[e], a, rad[..., -1])
        bx, by = self.base[e, 0], self.base[e, 1]
        return x0 + bx, y0 + by, x1 + bx, y1 + by


def pieces_distances(bodies: Bodies, a0: np.ndarray, turn: np.ndarray, ia: np.ndarray, ib: np.ndarray,
                     need: np.ndarray, resolution: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Least distance of each pair over each of ``S`` steps ``a0[s] + t·turn[s]``, all at once.

    Parameters
    ----------
    bodies : Bodies
        The robots and obstacles.
    a0, turn : numpy.ndarray, shape (S, N+M, J)
        Each step's start angles and turn of every entity (degrees).
    ia, ib : numpy.ndarray of int, shape (P,)
        The pairs checked (:meth:`Bodies.pairs`).
    need : numpy.ndarray, shape (P,)
        The distance (mm) each pair must keep.
    resolution : float
        Sampling step (mm): no point moves more than ``resolution/2`` between samples.

    Returns
    -------
    dmin, tmin : numpy.ndarray, shape (S, P)
        The least distance found (mm) and the ``t`` where it occurs (0 when the start is closest).
    unsure : numpy.ndarray of int, shape (S,)
        Per step, the pairs left open by the bisection.
    deep : numpy.ndarray, shape (S,)
        Per step, the deepest collision (mm) those pairs could hide.

    Notes
    -----
    Per step and pair, as the module docstring says: the end points first (``d(t)`` is
    ``L``-Lipschitz, so ``(d(0) + d(1) − L)/2 ≥ need`` clears a pair, its least distance then
    reported from the end points); the pairs left are sampled so that no point of the step's
    pairs moves more than ``resolution/2`` between samples; every interval the samples leave
    open is bisected, all of them a round at a time, until a sample collides, every bound
    clears ``need``, an interval's ``L·width/2`` is at most :data:`TOLERANCE` (the depth it
    could hide is reported) or a pair has more than :data:`MAX_OPEN` open intervals.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from supcoord.geometry.kinematics import Rotary
    >>> problem = SimpleNamespace(n=2, kin=lambda p: Rotary(1.0, 6), robot_kinematics=None,
    ...                           kinematics=Rotary(1.0, 6), buffers=[0.1, 0.1])
    >>> bodies = Bodies(problem, [[0.0, 0.0], [2.5, 0.0]])
    >>> a0 = np.array([[[90.0], [180.0], ]])           # both arms away from each other
    >>> turn = np.array([[[-90.0], [0.0]]])            # robot 0 swings to face robot 1
    >>> dmin, tmin, unsure, deep = pieces_distances(bodies, a0, turn, np.array([0]), np.array([1]),
    ...                                             np.array([0.2]), 0.05)
    >>> round(float(dmin[0, 0]), 6), float(tmin[0, 0])
    (0.5, 1.0)

    References
    ----------
    P. Hansen, B. Jaumard, S.-H. Lu, Global optimization of univariate Lipschitz functions,
    Mathematical Programming 55, 1992.
    """
    n_steps, n_pairs = len(a0), len(ia)
    travel = bodies.travel(turn)
    moving = np.any(turn != 0, axis=2)
    every = np.arange(len(bodies.base))
    start = bodies.place(every, a0)
    dmin = _ericson(*(x[:, ia] for x in start), *(x[:, ib] for x in start))
    tmin = np.zeros((n_steps, n_pairs))
    none = np.zeros(n_steps, dtype=np.int64), np.zeros(n_steps)
    sp, pp = np.nonzero(moving[:, ia] | moving[:, ib])
    if not len(sp):
        return dmin, tmin, *none
    # end points first: d(t) is L-Lipschitz, so (d(0) + d(1) − L)/2 ≥ need clears a pair at once
    end = bodies.place(every, a0 + turn)
    d_end = _ericson(*(x[sp, ia[pp]] for x in end), *(x[sp, ib[pp]] for x in end))
    lip = travel[sp, ia[pp]] + travel[sp, ib[pp]]
    clear = (dmin[sp, pp] + d_end - lip) / 2 >= need[pp]
    at_end = clear & (d_end < dmin[sp, pp])
    dmin[sp[at_end], pp[at_end]] = d_end[at_end]
    tmin[sp[at_end], pp[at_end]] = 1.0
    sp, pp, lip = sp[~clear], pp[~clear], lip[~clear]
    if not len(sp):
        return dmin, tmin, *none
    open_ = _Open(bodies, a0, turn, sp, ia[pp], ib[pp], lip, need[pp])
    top = np.full(n_steps, -np.inf)
    np.maximum.at(top, sp, np.maximum(travel[sp, ia[pp]], travel[sp, ib[pp]]))
    samples = np.maximum(1, np.ceil(2 * top / resolution)).astype(np.int64)  # per step, from its pairs left
    open_.sample(samples[sp])
    open_.bisect()
    dmin[sp, pp], tmin[sp, pp] = open_.dmin, open_.tmin
    left = (open_.depth > 0) & (open_.dmin >= open_.need)
    deep = np.zeros(n_steps)
    np.maximum.at(deep, sp[left], open_.depth[left])
    return dmin, tmin, np.bincount(sp[left], minlength=n_steps), deep


class _Open:
    """The (step, pair) entries their end points leave open: step ``s``, entities ``a``, ``b``,
    Lipschitz constant ``lip`` and distance needed ``need``; the least distance ``dmin`` found
    and where (``tmin``), and ``depth``, the deepest collision the bisection left possible."""

    def __init__(self, bodies: Bodies, a0: np.ndarray, turn: np.ndarray, s: np.ndarray, a: np.ndarray,
                 b: np.ndarray, lip: np.ndarray, need: np.ndarray):
        self.bodies, self.a0, self.turn = bodies, a0, turn
        self.s, self.a, self.b, self.lip, self.need = s, a, b, lip, need
        self.dmin, self.tmin = np.zeros(len(s)), np.zeros(len(s))
        self.depth = np.zeros(len(s))
        self.work = np.zeros((0, 5))  # undecided intervals: (entry, t0, t1, d0, d1)

    def distances(self, j: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Distances of entries ``j`` ``(K,)`` at times ``t`` ``(K, T)`` of their steps."""
        s, a, b = self.s[j], self.a[j], self.b[j]
        qa = self.a0[s, a][:, None, :] + t[:, :, None] * self.turn[s, a][:, None, :]
        qb = self.a0[s, b][:, None, :] + t[:, :, None] * self.turn[s, b][:, None, :]
        return _ericson(*self.bodies.place(a[:, None], qa), *self.bodies.place(b[:, None], qb))

    def sampled(self, j: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Distances ``(K, T)`` of entries ``j`` ``(K,)`` at the times ``t`` ``(T,)`` of their
        steps: each (step, entity) placed once at every time, however many pairs it is in."""
        n_ent = len(self.bodies.base)
        key, inverse = np.unique(np.concatenate([self.s[j] * n_ent + self.a[j], self.s[j] * n_ent + self.b[j]]),
                                 return_inverse=True)
        s, e = np.divmod(key, n_ent)
        q = self.a0[s, e][:, None, :] + t[None, :, None] * self.turn[s, e][:, None, :]
        placed = self.bodies.place(e[:, None], q)
        ra, rb = inverse[:len(j)], inverse[len(j):]
        return _ericson(*(x[ra] for x in placed), *(x[rb] for x in placed))

    def sample(self, samples: np.ndarray) -> None:
        """Sample entry ``j`` at ``samples[j] + 1`` equal times; keep the least distance and the
        intervals whose bound does not settle it."""
        rows = []
        for count in np.unique(samples).tolist():
            t = np.linspace(0.0, 1.0, count + 1)
            group = np.nonzero(samples == count)[0]
            per = max(1, _ROWS // len(t))
            for lo in range(0, len(group), per):
                j = group[lo:lo + per]
                dist = self.sampled(j, t)
                best = dist.argmin(axis=1)
                self.dmin[j] = dist[np.arange(len(j)), best]
                self.tmin[j] = t[best]
                bound = (dist[:, :-1] + dist[:, 1:] - self.lip[j, None] / count) / 2
                need = self.need[j, None]
                pi, ti = np.nonzero((bound < need) & (self.dmin[j, None] >= need))
                if len(pi):
                    rows.append(np.stack([j[pi], t[ti], t[ti + 1], dist[pi, ti], dist[pi, ti + 1]], axis=1))
        if rows:
            self.work = np.concatenate(rows)

    def bisect(self) -> None:
        """Halve every open interval, a round at a time (the class docstring's ``depth``)."""
        lip, need = self.lip, self.need
        work = self.work
        while len(work):
            j = work[:, 0].astype(int)
            crowded = np.bincount(j, minlength=len(lip))[j] > MAX_OPEN  # a contact along a stretch: stop there
            if crowded.any():
                gap = need[j] - (work[:, 3] + work[:, 4] - lip[j] * (work[:, 2] - work[:, 1])) / 2
                np.maximum.at(self.depth, j[crowded], gap[crowded])
                work = work[~crowded]
                continue
            mid = (work[:, 1] + work[:, 2]) / 2
            dm = np.concatenate([self.distances(j[lo:lo + _ROWS], mid[lo:lo + _ROWS, None])[:, 0]
                                 for lo in range(0, len(j), _ROWS)])
            better = dm < self.dmin[j]
            np.minimum.at(self.dmin, j, dm)
            self.tmin[j[better]] = mid[better]
            halves = np.concatenate([np.stack([j, work[:, 1], mid, work[:, 3], dm], axis=1),
                                     np.stack([j, mid, work[:, 2], dm, work[:, 4]], axis=1)])
            k = halves[:, 0].astype(int)
            width = halves[:, 2] - halves[:, 1]
            bound = (halves[:, 3] + halves[:, 4] - lip[k] * width) / 2
            alive = (bound < need[k]) & (self.dmin[k] >= need[k])  # a collision found ends the pair
            settled = alive & (lip[k] * width / 2 <= TOLERANCE)
            np.maximum.at(self.depth, k[settled], need[k[settled]] - bound[settled])
            work = halves[alive & ~settled]


def _close_pairs(bases: np.ndarray, limit: float) -> tuple[np.ndarray, np.ndarray]:
    """All ``(a, b)``, ``a < b``, with bases closer than ``limit``, ordered by ``a`` then ``b``:
    candidates from a k-d tree (:meth:`scipy.spatial.cKDTree.query_pairs`, a radius a
    billionth wider so that no rounding of its distance loses a pair), then the distance
    ``hypot(Δx, Δy) < limit`` decided here (memory and time grow with the pairs, not N²)."""
    if len(bases) < 2:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    from scipy.spatial import cKDTree  # imported here: 0.4 s of start-up that the commands
    # which never search for neighbours (paper, supcon, force, their study cases) need not pay

    found = cKDTree(bases).query_pairs(limit * (1 + 1e-9) + 1e-12, output_type="ndarray").astype(np.int64)
    a, b = found.min(axis=1), found.max(axis=1)
    keep = np.hypot(*(bases[a] - bases[b]).T) < limit
    a, b = a[keep], b[keep]
    order = np.lexsort((b, a))
    return a[order], b[order]


@dataclass(frozen=True)
class MotionCheck:
    """What the geometric check of a motion found: colliding (step, pair) incidents, the
    least clearance ``dist − (r_a + r_b)`` (mm, ``inf`` when no pair was checked), the first
    incidents (:class:`~.validation_result.Incident`), the
    pairs left undecided and how deep a collision they could hide (mm)."""

    collisions: int = 0
    clearance: float = math.inf
    incidents: list[Incident] = field(default_factory=list)
    undecided: int = 0
    depth: float = 0.0

    def plus(self, other: MotionCheck) -> MotionCheck:
        """Both checks' findings (the incidents listed are this check's)."""
        return MotionCheck(self.collisions + other.collisions, min(self.clearance, other.clearance), self.incidents,
                           self.undecided + other.undecided, max(self.depth, other.depth))


@dataclass
class _Found:
    """What the check has found so far (:class:`MotionCheck`'s fields)."""

    collisions: int = 0
    clearance: float = math.inf
    incidents: list[Incident] = field(default_factory=list)
    undecided: int = 0
    depth: float = 0.0


@dataclass
class _Step:
    """One step of a motion as checked: what reading it reported (``said``), the turn refused
    (``refused``, degrees, when more than :data:`MAX_TURNS` turns) or its pieces (one per
    turn); its least distance ``dmin`` and where (``tmin``) per pair, combined piece by piece
    until ``done`` reaches ``pieces``, then only its collisions: the pairs ``hits``, their
    least distances and times."""

    said: list[str]
    pieces: int
    refused: float | None = None
    dmin: np.ndarray | None = None
    tmin: np.ndarray | None = None
    done: int = 0
    hits: np.ndarray | None = None


class MotionChecker:
    """The certified collision check of motions among ``problem``'s robots on ``bases``: the
    pairs that can meet (:meth:`Bodies.pairs`), each needing ``dist ≥ r_a + r_b``, sampled at
    ``resolution`` (mm) then bisected (:func:`pieces_distances`, for blocks of steps at once);
    at most ``max_incidents`` incidents are listed."""

    def __init__(self, problem: Any, bases: np.ndarray, resolution: float, max_incidents: int):
        self.bodies = Bodies(problem, bases)
        self.ia, self.ib = self.bodies.pairs()
        self.need = self.bodies.buffers[self.ia] + self.bodies.buffers[self.ib]
        self.resolution, self.max_incidents = resolution, max_incidents

    def check(self, step: Callable[[int], tuple[np.ndarray, np.ndarray]], count: int, single: str,
              problems: list[str]) -> MotionCheck:
        """Check ``count`` poses, ``step(k)`` giving pose ``k``'s angles ``(N, J)`` (degrees) and
        the turn to pose ``k + 1``; each collision is appended to ``problems`` (a one-pose
        motion is named ``single``), after what ``step(k)`` reported, step by step."""
        head = len(problems)
        steps: list[_Step] = []
        block: list[tuple[int, int, np.ndarray, np.ndarray]] = []  # pieces: (step, piece, start, turn)
        per_block = max(1, _ENTRIES // max(1, len(self.ia)))
        found = _Found()
        for k in range(max(1, count - 1)):
            a0, turn = step(k)
            steps.append(_Step(problems[head:], 1))
            del problems[head:]
            a0, turn = self.bodies.pad(a0), self.bodies.pad(turn)
            # a step turning a joint by more than a turn is checked a turn at a time (the same motion)
            pieces = max(1, math.ceil(float(np.abs(turn).max(initial=0.0)) / 360.0))
            if pieces > MAX_TURNS:
                steps[k].refused = float(np.abs(turn).max())
                continue
            steps[k].pieces = pieces
            part = turn / pieces
            for i in range(pieces):
                block.append((k, i, a0 + i * part, part))
                if len(block) >= per_block:
                    self._run(block, steps, found)
                    block = []
        self._run(block, steps, found)
        for k, st in enumerate(steps):
            where = f"step {k}->{k + 1}" if count > 1 else single
            problems.extend(st.said)
            if st.refused is not None:
                problems.append(f"{where}: a joint turns by {st.refused:.6g} deg, more than {MAX_TURNS} "
                                f"turns: not checked for collisions")
            else:
                self._report(k, where, st, found, problems)
        return MotionCheck(found.collisions, found.clearance, found.incidents, found.undecided, found.depth)

    def _run(self, block: list[tuple[int, int, np.ndarray, np.ndarray]], steps: list[_Step], found: _Found) -> None:
        """Check a block of pieces at once; fold each piece into its step, in order."""
        if not block:
            return
        a0, turn = np.stack([b[2] for b in block]), np.stack([b[3] for b in block])
        dmin, tmin, unsure, deep = pieces_distances(self.bodies, a0, turn, self.ia, self.ib, self.need - TIE,
                                                    self.resolution)
        for row, (k, i, _, _) in enumerate(block):
            st = steps[k]
            if st.dmin is None:
                st.dmin, st.tmin = np.full(len(self.ia), np.inf), np.zeros(len(self.ia))
            d, t = dmin[row], tmin[row]
            st.tmin = np.where(d < st.dmin, (i + t) / st.pieces, st.tmin)
            st.dmin = np.minimum(st.dmin, d)
            found.undecided += int(unsure[row])
            found.depth = max(found.depth, float(deep[row]))
            st.done += 1
            if st.done == st.pieces:
                if len(st.dmin):
                    found.clearance = min(found.clearance, float(np.min(st.dmin - self.need)))
                st.hits = np.nonzero(st.dmin < self.need - TIE)[0]
                st.dmin, st.tmin = st.dmin[st.hits], st.tmin[st.hits]

    def _report(self, k: int, where: str, st: _Step, found: _Found, problems: list[str]) -> None:
        """Step ``k``'s collisions: counted, appended to ``problems``, the first ones listed as incidents."""
        need, n = self.need, self.bodies.n
        found.collisions += len(st.hits)
        for h, d, t in zip(st.hits, st.dmin, st.tmin):
            a, b = int(self.ia[h]), int(self.ib[h])
            what = f"positioners {a} and {b} collide" if b < n else f"positioner {a} collides with obstacle {b - n}"
            problems.append(f"{where}: {what} (distance {d:.3f} mm < {need[h]:.3f} mm)")
            if len(found.incidents) < self.max_incidents:
                found.incidents.append(Incident(k, [a, b] if b < n else [a], float(t), float(d), float(need[h]),
                                                None if b < n else b - n))
