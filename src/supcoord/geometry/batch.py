"""Swept tables of many pairs at once, for layouts whose robots each have their own geometry.

:func:`.collision.swept_table` decides one pair's moves with a few numpy calls each; a real
focal plane (each robot its own arms and lattice) has thousands of distinct pairs, and
the time then goes into the calls, not the arithmetic.  :func:`batch_swept` computes the
same tables — the same end-point prefilter and the same exact closed form
(:func:`.sweep.rotation_clearance`) on the same numbers — for a whole chunk of pairs.
Each robot's segments, successors, rotations and sampled poses are computed once per
distinct kinematics.

Between the two, the sound cheap tests of :func:`.sweep.rotation_certain` decide most
entries the prefilter leaves open: the sampled bound over the whole turn (per table), the
annulus, then the bisected turn (:func:`.sweep.bisect_turns`) over the whole chunk; one
clearance call takes what is still open.  The tests decide only with :data:`.sweep.MARGIN`
to spare, so every entry is what the closed form makes it: the tables are the same booleans.

Most position pairs of two robots hold arms far apart: a distance is computed exactly only
where a cheap lower bound (midpoints' distance less the half-lengths, :func:`_far_bounds`)
leaves the end-point prefilter open; an entry whose prefilter used a bound and stays open
gets its exact end-point distances before anything else reads them, so every later step
sees the numbers it always saw.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .joint_space import Kinematics
from .segments import segment_distance
from .sweep import (
    MARGIN,
    _rotate,
    annulus_clear,
    bisect_turns,
    rotation_clearance,
    turn_radii,
    turn_slack,
)

__all__ = ["KinematicsArrays", "batch_swept"]

#: bisections of a turn before the closed form (:func:`.sweep.bisect_turns`): poses at k/4
_DEPTH = 2
#: slack of the distance lower bound against rounding (mm)
_BOUND_SLACK = 1e-9
#: tables of fewer position pairs get every distance exactly and the dense prefilter (the
#: bounds' extra numpy calls cost more than they save there: the APO wok at 13 × 7, 8,281
#: entries, took 1.9 s longer to tabulate)
BOUND_MIN_ENTRIES = 20_000


def _far_bounds(sa: np.ndarray, sb: np.ndarray, threshold: float) -> tuple[np.ndarray, np.ndarray]:
    """``(D, exact)``: ``D[i, j]`` the distance between segments ``sa[i]`` and ``sb[j]`` where
    ``exact[i, j]`` (everywhere below :data:`BOUND_MIN_ENTRIES` entries), elsewhere
    ``threshold``, a lower bound: there
    ``|m_a − m_b| ≥ threshold + h_a + h_b`` (midpoints ``m``, half-lengths ``h``; every point
    of a segment lies within ``h`` of its midpoint), tested on squares with
    :data:`_BOUND_SLACK` to spare."""
    if len(sa) * len(sb) < BOUND_MIN_ENTRIES:
        exact = np.ones((len(sa), len(sb)), dtype=bool)
        return segment_distance(sa[:, None, 0], sa[:, None, 1], sb[None, :, 0], sb[None, :, 1]), exact
    ma, mb = sa.mean(axis=1), sb.mean(axis=1)
    ha = np.hypot(*(sa[:, 1] - sa[:, 0]).T) / 2
    hb = np.hypot(*(sb[:, 1] - sb[:, 0]).T) / 2
    dx = ma[:, None, 0] - mb[None, :, 0]
    dy = ma[:, None, 1] - mb[None, :, 1]
    dx *= dx
    dy *= dy
    dx += dy
    reach = (ha + (threshold + _BOUND_SLACK))[:, None] + hb[None, :]
    reach *= reach
    exact = dx < reach
    out = np.full(exact.shape, float(threshold))
    i, j = np.nonzero(exact)
    out[i, j] = segment_distance(sa[i, 0], sa[i, 1], sb[j, 0], sb[j, 1])
    return out, exact


class KinematicsArrays:
    """One kinematics' positions as arrays: segments ``S[i]`` (relative to the base) and, per
    move ``m``, the successor ``nxt[m, i]`` (−1 past a hard stop), the turn's centre and
    angle (:meth:`Kinematics.rotation`) and the sweep length.  For :func:`batch_swept`: where a
    move runs into a stop (``stop[m, i]``; ``nxt_or_self`` is ``i`` there), the sampled poses
    ``poses[m, i, k]`` (``S_i`` turned by ``k/2**_DEPTH`` of the move, as ``(px, py, qx, qy)``),
    the turn radii ``r_min``, ``r_max`` (:func:`.sweep.turn_radii`) and ``slack[m, i, l]``
    (:func:`.sweep.turn_slack` of ``2**l`` pieces)."""

    def __init__(self, kin: Kinematics):
        pos = kin.all_positions()
        self.segments = kin.segments(pos)
        moves = kin.moves()
        self.nxt = np.full((len(moves), len(pos)), -1, dtype=np.int64)
        self.centre = np.zeros((len(moves), len(pos), 2))
        self.angle = np.zeros((len(moves), len(pos)))
        self.length = np.zeros(len(moves))
        for m, (joint, delta) in enumerate(moves):
            nxt, ok = kin.step_array(pos, joint, delta)
            idx = np.nonzero(ok)[0]
            self.nxt[m, idx] = kin.flat_index(nxt[idx])
            if len(idx):
                c, a = kin.rotation(pos[idx], joint, np.full(len(idx), float(delta)))
                self.centre[m, idx], self.angle[m, idx] = c, a
            d = np.zeros(kin.n_joints)
            d[joint] = delta
            self.length[m] = float(kin.sweep_length(d))
        self.turn_samples()

    def turn_samples(self) -> None:
        """Compute ``stop``, ``poses``, ``r_min``, ``r_max`` and ``slack`` (class docstring)."""
        self.stop = self.nxt < 0
        self.nxt_or_self = np.where(self.stop, np.arange(self.nxt.shape[1]), self.nxt)
        width = 2 ** _DEPTH
        turn = self.angle[:, :, None] * (np.arange(width + 1) / width)  # (M, P, K)
        centre = self.centre[:, :, None, :]
        ends = [_rotate(self.segments[None, :, None, e, :], centre, turn) for e in (0, 1)]
        self.poses = np.ascontiguousarray(np.concatenate(ends, axis=-1))  # (M, P, K, 4)
        self.r_min, self.r_max = turn_radii(self.segments[None], self.centre)
        self.slack = np.stack([turn_slack(self.r_max, self.angle, 2 ** level) for level in range(_DEPTH + 1)],
                              axis=-1)


def _prefilter(km: KinematicsArrays, d: np.ndarray, exact: np.ndarray, bsum: float) -> tuple[np.ndarray, ...]:
    """The end-point prefilter of every move at once: ``W[m, i, j]`` True where either end
    pose collides (``d0 < bsum`` or ``d1 < bsum``) or the move runs into a stop; the entries
    left open ``(flat, rows, d0, d1)`` are those neither that nor ``(d0 + d1 − L)/2 ≥ bsum``
    decides.  Only entries with an end pose at an exact distance are looked at: where both
    ends hold bounds ``≥ bsum + L/2`` (:func:`_far_bounds`) the move is free."""
    n_moves, n_pos = km.nxt.shape
    n_other = d.shape[1]
    if n_pos * n_other < BOUND_MIN_ENTRIES:  # every distance exact: one dense pass is cheaper
        d1 = d[km.nxt_or_self]  # (M, P, P')
        near = d < bsum
        w = near[km.nxt_or_self]
        w |= near
        w |= km.stop[:, :, None]
        lower = np.add(d, d1)
        lower -= km.length[:, None, None]
        decided = lower >= 2 * bsum
        decided |= w
        flat = np.flatnonzero(~decided)
        row = flat // n_other
        return w, flat, row, d.reshape(-1)[flat % d.size], d1.reshape(-1)[flat]
    w = np.empty((n_moves, n_pos, n_other), dtype=bool)
    w[:] = km.stop[:, :, None]
    cand = exact[km.nxt_or_self]  # (M, P, P'): the end pose's distance is exact …
    cand |= exact  # … or the start pose's
    cand &= ~km.stop[:, :, None]  # (a move into a stop is decided)
    flat = np.flatnonzero(cand)
    row, j = np.divmod(flat, n_other)
    m, i = np.divmod(row, n_pos)
    e0 = d[i, j]
    e1 = d[km.nxt_or_self[m, i], j]
    hit = (e0 < bsum) | (e1 < bsum)
    w.reshape(-1)[flat[hit]] = True
    lower = np.add(e0, e1)  # d0 + d1 − L ≥ 2·bsum is (d0 + d1 − L)/2 ≥ bsum: halving is exact
    lower -= km.length[m]
    keep = ~hit & ~(lower >= 2 * bsum)
    return w, flat[keep], row[keep], e0[keep], e1[keep]


def _exact_ends(flat: np.ndarray, row: np.ndarray, e0: np.ndarray, e1: np.ndarray, exact: np.ndarray,
                km: KinematicsArrays, seg_m: np.ndarray, seg_s: np.ndarray, bsum: float) -> tuple[np.ndarray, ...]:
    """The open entries ``flat`` (rows ``m·P + i``, end-point distances ``e0``, ``e1``) with
    their bounded end-point distances made exact, and those the exact end-point bound
    ``(e0 + e1 − L)/2 ≥ bsum`` then decides (free) dropped: the same test, on the same
    numbers, as without the bounds."""
    n_other = seg_s.shape[0]
    i, j = row % seg_m.shape[0], flat % n_other
    i1 = km.nxt_or_self.reshape(-1)[row]
    redo = ~(exact[i, j] & exact[i1, j])
    if not redo.any():
        return flat, row, e0, e1
    e0, e1 = e0.copy(), e1.copy()
    r, jr = np.nonzero(redo)[0], j[redo]
    e0[r] = segment_distance(seg_m[i[r], 0], seg_m[i[r], 1], seg_s[jr, 0], seg_s[jr, 1])
    e1[r] = segment_distance(seg_m[i1[r], 0], seg_m[i1[r], 1], seg_s[jr, 0], seg_s[jr, 1])
    lower = np.add(e0, e1)
    lower -= km.length[row // seg_m.shape[0]]
    keep = lower < 2 * bsum
    return flat[keep], row[keep], e0[keep], e1[keep]


def batch_swept(arrays_a: list[KinematicsArrays], arrays_b: list[KinematicsArrays], offsets: Any,
                bsums: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``[(T, W0, W1), …]`` for pairs ``k`` with ``a`` at the origin and ``b`` at ``offsets[k]``:
    the static table ``T[i, j] = D[i, j] < bsum`` and the swept tables of ``a`` moving
    (``W0[m, i, j]``) and of ``b`` moving (``W1[m, i, j]``), as :func:`.collision.swept_table`
    defines them."""
    offsets = np.asarray(offsets, float).reshape(-1, 2)
    out: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    # the open entries of each table (neither end pose nor the bound over the whole turn
    # decides them): the table, flat indices f = (m·P + i)·P' + j, rows m·P + i, distances d0,
    # d1; and where the table's data lie in the blocks below
    jobs: list[tuple[np.ndarray, np.ndarray]] = []
    rows, d0s, d1s, counts, heights, widths, job_bsum = [], [], [], [], [], [], []
    at_kin, at_mover, at_turn, at_other = [], [], [], []
    kin_at: dict[int, int] = {}
    kins: list[KinematicsArrays] = []  # blocks: turn data per distinct kinematics (mover's frame)
    movers, centres, angles, others, frames = [], [], [], [], []  # blocks per table
    n_kin = n_mover = n_turn = n_other = 0
    for ka, kb, off, bsum in zip(arrays_a, arrays_b, offsets, np.asarray(bsums, float)):
        sa, sb = ka.segments, kb.segments + off
        # exact where either end pose could be near or the end-point bound could fail
        dist, known = _far_bounds(sa, sb, bsum + max(ka.length.max(initial=0.0), kb.length.max(initial=0.0)) / 2)
        tables = []
        for mover, (km, seg_m, seg_s, shift, d, exact) in enumerate((
                (ka, sa, sb, 0.0, dist, known),
                (kb, sb, sa, off, np.ascontiguousarray(dist.T), np.ascontiguousarray(known.T)))):
            w, flat, row, e0, e1 = _prefilter(km, d, exact, bsum)
            n_pos, n_other_pos = d.shape
            if len(flat):
                flat, row, e0, e1 = _exact_ends(flat, row, e0, e1, exact, km, seg_m, seg_s, bsum)
            if len(flat):
                # the sampled bound over the whole turn (level 0 of sweep.bisect_turns)
                keep = (e0 + e1) * 0.5 - km.slack.reshape(-1, _DEPTH + 1)[row, 0] < bsum + MARGIN
                if keep.any():
                    if id(km) not in kin_at:
                        kin_at[id(km)] = n_kin
                        kins.append(km)
                        n_kin += km.slack.shape[0] * n_pos
                    jobs.append((w, flat[keep]))
                    rows.append(row[keep])
                    d0s.append(e0[keep])
                    d1s.append(e1[keep])
                    counts.append(int(np.count_nonzero(keep)))
                    heights.append(n_pos)
                    widths.append(n_other_pos)
                    job_bsum.append(bsum)
                    at_kin.append(kin_at[id(km)])
                    at_mover.append(n_mover)
                    at_turn.append(n_turn)
                    at_other.append(n_other)
            movers.append(seg_m)
            centres.append((km.centre + shift).reshape(-1, 2))
            angles.append(km.angle.reshape(-1))
            others.append(seg_s)
            frames.append((seg_s - shift).reshape(-1, 4))  # the standing segments in the mover's frame
            n_mover += n_pos
            n_turn += len(km.nxt) * n_pos
            n_other += n_other_pos
            tables.append(w)
        out.append((dist < bsum, tables[0], np.swapaxes(tables[1], 1, 2)))
    if not jobs:
        return out
    counts = np.asarray(counts)
    flat, row = np.concatenate([f for _, f in jobs]), np.concatenate(rows)
    d0, d1 = np.concatenate(d0s), np.concatenate(d1s)
    bsum = np.repeat(np.asarray(job_bsum), counts)
    krow = np.repeat(np.asarray(at_kin), counts) + row
    ocol = np.repeat(np.asarray(at_other), counts) + (flat - row * np.repeat(np.asarray(widths), counts))
    # the annulus, then the bisected turn, in the mover's frame
    r_min = np.concatenate([k.r_min.reshape(-1) for k in kins])[krow]
    r_max = np.concatenate([k.r_max.reshape(-1) for k in kins])[krow]
    centre = np.concatenate([k.centre.reshape(-1, 2) for k in kins])[krow]
    frame = np.concatenate(frames)
    todo = np.nonzero(~annulus_clear(centre, r_min, r_max, frame[ocol].reshape(-1, 2, 2), bsum))[0]
    kr, oc = krow[todo], ocol[todo]
    poses = np.concatenate([k.poses.reshape(-1, 2 ** _DEPTH + 1, 4) for k in kins])
    slack = np.concatenate([k.slack.reshape(-1, _DEPTH + 1) for k in kins])[kr]

    def pose_distance(e: np.ndarray, k: np.ndarray) -> np.ndarray:
        p, t = poses[kr[e], k], frame[oc[e]]
        return segment_distance(p[:, 0:2], p[:, 2:4], t[:, 0:2], t[:, 2:4])

    hit, open_ = bisect_turns(d0[todo], d1[todo], slack, bsum[todo], pose_distance, _DEPTH)
    result = np.zeros(len(d0), dtype=bool)
    result[todo[hit]] = True
    exact = todo[open_]
    if len(exact):  # the closed form, on the very numbers the tables always used
        trow = np.repeat(np.asarray(at_turn), counts)[exact] + row[exact]
        i = row[exact] % np.repeat(np.asarray(heights), counts)[exact]
        mrow = np.repeat(np.asarray(at_mover), counts)[exact] + i
        clearance = rotation_clearance(np.concatenate(movers)[mrow], np.concatenate(centres)[trow],
                                       np.concatenate(angles)[trow], np.concatenate(others)[ocol[exact]])
        result[exact] = clearance < bsum[exact]
    at = 0  # the open entries are False so far: set the collisions
    for (w, f), n in zip(jobs, counts):
        w.reshape(-1)[f[result[at:at + n]]] = True
        at += n
    return out
