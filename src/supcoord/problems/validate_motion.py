"""The validator's own geometry: arms, segment distances, and the certified check of one step.

Part of :mod:`.validate` (see its docstring for the rule), kept apart only for size; like
it, deliberately independent of :mod:`supcoord.geometry`: the arms are recomputed from the
PROBLEM.json numbers, segment distances by Ericson's clamped closest points, and each step
``c_0 + t·Δ`` is sampled and then bisected with the pair's Lipschitz bound.

References
----------
- C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann 2005, §5.1.9.
- P. Hansen, B. Jaumard, S.-H. Lu, Global optimization of univariate Lipschitz functions,
  Mathematical Programming 55, 1992.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["segment_distance_ericson", "TOLERANCE", "MAX_OPEN"]

#: depth (mm) below which bisection stops: a collision shallower than this can pass unseen
TOLERANCE = 1e-6
#: intervals bisected at once (bounds the memory of one round)
_ROWS = 200_000
#: open intervals of one pair and step beyond which bisection stops: the pair touches along
#: a stretch (distance exactly ``r_a + r_b``), which no sampling can settle; the result
#: reports how deep a collision there could be (``undecided_depth``)
MAX_OPEN = 64


def segment_distance_ericson(p1: Any, q1: Any, p2: Any, q2: Any) -> np.ndarray:
    """Distance between segments ``[p1, q1]`` and ``[p2, q2]`` via clamped closest parameters.

    Every candidate is the distance between two actual points of the segments, so the
    result is never below the true distance; the end-point candidates make it exact
    also for nearly parallel segments.

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
    return np.minimum(d, np.minimum(np.minimum(ends[0], ends[1]), np.minimum(ends[2], ends[3])))


def _to_segment(x: np.ndarray, start: np.ndarray, direction: np.ndarray, length2: np.ndarray) -> np.ndarray:
    u = _dot(x - start, direction) / np.where(length2 > 0, length2, 1.0)
    u = np.clip(u, 0.0, 1.0)
    w = start + u[..., None] * direction - x
    return np.sqrt(_dot(w, w))


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]


def _arm(kin: dict, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
    """Colliding segment (start, end) relative to the base for float positions ``q`` (..., J),
    the sum of the arm lengths, and per-joint angle increments (radians per step)."""
    if kin["kind"] == "rotary":
        theta = -2.0 * math.pi * q[..., 0] / kin["steps"]
        end = kin["arm"] * np.stack([np.cos(theta), np.sin(theta)], -1)
        return np.zeros_like(end), end, kin["arm"], np.array([2 * math.pi / kin["steps"]])
    lo, hi = (math.radians(v) for v in kin["beta_range"])
    alpha = 2.0 * math.pi * q[..., 0] / kin["alpha_steps"]
    beta = lo + (hi - lo) * q[..., 1] / (kin["beta_steps"] - 1)
    elbow = kin["alpha"] * np.stack([np.cos(alpha), np.sin(alpha)], -1)
    fibre = elbow + kin["beta"] * np.stack([np.cos(alpha + beta), np.sin(alpha + beta)], -1)
    incr = np.array([2 * math.pi / kin["alpha_steps"], (hi - lo) / (kin["beta_steps"] - 1)])
    return elbow, fibre, kin["alpha"] + kin["beta"], incr


def _step_distances(kin: dict, bases: np.ndarray, c0: np.ndarray, delta: np.ndarray, ia: np.ndarray,
                    ib: np.ndarray, travel: np.ndarray, need: np.ndarray,
                    resolution: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Least distance of each pair ``(ia, ib)`` over the step ``c0 + t·delta``, the ``t`` where
    it occurs (0 when the start is closest) and the number of pairs left undecided within
    :data:`TOLERANCE`: sampled so that no point moves more than ``resolution/2`` between
    samples, then bisected where the samples do not settle ``d ≥ need`` (module docstring);
    the last value is ``(pairs left open, the deepest collision they could hide)``."""
    moving = np.any(delta != 0, axis=1)
    sel = np.nonzero(moving[ia] | moving[ib])[0]
    d_static = _pair_distances(kin, bases, c0.astype(float), ia, ib)
    dmin, tmin = d_static.copy(), np.zeros(len(ia))
    if not len(sel):
        return dmin, tmin, (0, 0.0)
    lip = travel[ia[sel]] + travel[ib[sel]]  # d(t) is L-Lipschitz for the pair
    samples = max(1, math.ceil(2 * float(travel.max()) / resolution))
    t = np.linspace(0.0, 1.0, samples + 1)
    rows: list[np.ndarray] = []  # undecided intervals: (pair, t0, t1, d0, d1)
    per = max(1, _ROWS // len(t))
    for lo in range(0, len(sel), per):
        idx = np.arange(lo, min(lo + per, len(sel)))
        dist = _distances_at(kin, bases, c0, delta, ia[sel[idx]], ib[sel[idx]], np.broadcast_to(t, (len(idx), len(t))))
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
        dm = _distances_at(kin, bases, c0, delta, ia[sel[j]], ib[sel[j]], mid[:, None])[:, 0]
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


def _distances_at(kin: dict, bases: np.ndarray, c0: np.ndarray, delta: np.ndarray, a: np.ndarray, b: np.ndarray,
                  t: np.ndarray) -> np.ndarray:
    """Distances of the pairs ``(a[i], b[i])`` at the times ``t[i, :]`` of the step ``c0 + t·delta``."""
    qa = c0[a][:, None, :] + t[:, :, None] * delta[a][:, None, :]
    qb = c0[b][:, None, :] + t[:, :, None] * delta[b][:, None, :]
    a0, a1, _, _ = _arm(kin, qa)
    b0, b1, _, _ = _arm(kin, qb)
    ba, bb = bases[a][:, None, :], bases[b][:, None, :]
    return segment_distance_ericson(a0 + ba, a1 + ba, b0 + bb, b1 + bb)


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


def _pair_distances(kin: dict, bases: np.ndarray, c: np.ndarray, ia: np.ndarray, ib: np.ndarray) -> np.ndarray:
    s0, s1, _, _ = _arm(kin, c)
    s0, s1 = s0 + bases, s1 + bases
    return segment_distance_ericson(s0[ia], s1[ia], s0[ib], s1[ib])
