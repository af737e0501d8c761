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
where a cheap lower bound (midpoints' distance less the half-lengths, :func:`_far_bounds`,
found with a k-d tree) leaves the end-point prefilter open; an entry whose prefilter used a
bound and stays open gets its exact end-point distances before anything else reads them, so
every later step sees the numbers it always saw.

Only half the moves are decided: a move and its reverse (the same joint, the other way)
travel the same poses, so the reverse's rows are the forward move's, shifted by one step
(:func:`reversals`, :meth:`.Kinematics.reversed_moves`); the pair-by-pair
:func:`.collision.swept_table` fills them the same way.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import SupcoordError
from .joint_space import Kinematics
from .segments import BLOCK, segment_coords, segment_distance, segment_distance_xy
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
#: open entries decided together (as :data:`.segments.BLOCK`: small temporaries are much faster)
DECIDE_BLOCK = BLOCK


def _far_bounds(sa: np.ndarray, sb: np.ndarray, threshold: float,
                scratch: dict | None = None) -> tuple[np.ndarray, ...]:
    """``(D, exact, Dᵀ, exactᵀ)``: ``D[i, j]`` the distance between segments ``sa[i]`` and
    ``sb[j]`` where ``exact[i, j]`` (everywhere below :data:`BOUND_MIN_ENTRIES` entries),
    elsewhere ``threshold``, a lower bound: there the midpoints are farther apart than
    ``threshold + max h_a + max h_b`` (half-lengths ``h``; every point of a segment lies within
    ``h`` of its midpoint) with :data:`_BOUND_SLACK` to spare.  The near midpoint pairs come
    from a k-d tree (:meth:`scipy.spatial.cKDTree.sparse_distance_matrix`, with room for its
    rounding); the transposes are built directly (the other robot moving reads them by rows).
    ``scratch``: arrays to reuse, by shape and type (valid until the next call with it)."""
    if len(sa) * len(sb) < BOUND_MIN_ENTRIES:
        dist = segment_distance(sa[:, None, 0], sa[:, None, 1], sb[None, :, 0], sb[None, :, 1])
        return dist, np.ones(dist.shape, dtype=bool), np.ascontiguousarray(dist.T), np.ones(dist.shape[::-1], dtype=bool)
    ma, mb = sa.mean(axis=1), sb.mean(axis=1)
    ha = np.hypot(*(sa[:, 1] - sa[:, 0]).T) / 2
    hb = np.hypot(*(sb[:, 1] - sb[:, 0]).T) / 2
    radius = (float(ha.max()) + (threshold + _BOUND_SLACK) + float(hb.max())) * (1 + 1e-9) + 1e-9
    from scipy.spatial import cKDTree  # imported here: 0.4 s of start-up that the commands
    # which never search for neighbours (paper, supcon, force, their study cases) need not pay

    near = cKDTree(ma).sparse_distance_matrix(cKDTree(mb), radius, output_type="ndarray")
    i, j = near["i"].astype(np.int64), near["j"].astype(np.int64)
    ca, cb = segment_coords(sa), segment_coords(sb)
    values = np.empty(len(i))
    for lo in range(0, len(i), BLOCK):
        part = slice(lo, lo + BLOCK)
        values[part] = segment_distance_xy(*ca[:, i[part]], *cb[:, j[part]])
    scratch = {} if scratch is None else scratch
    out = []
    for side, (rows, cols, shape) in enumerate(((i, j, (len(sa), len(sb))), (j, i, (len(sb), len(sa))))):
        dist, exact = _buffer(scratch, f"dist{side}", shape, float), _buffer(scratch, f"exact{side}", shape)
        dist.fill(threshold)  # a fresh array would cost a new memory map and its page faults
        dist[rows, cols] = values
        exact.fill(False)
        exact[rows, cols] = True
        out += [dist, exact]
    return tuple(out)


def reversals(kin: Kinematics) -> list[tuple[int, int, np.ndarray, np.ndarray]]:
    """``[(r, m, rows, stop), …]`` for every reversed move ``r`` of its forward move ``m``
    (:meth:`.Kinematics.reversed_moves`): ``W_r[i] = W_m[rows[i]]`` (``rows[i] = step_r(i)``),
    and ``True`` where ``stop[i]`` (the move runs into a hard stop)."""
    pos = kin.all_positions()
    out = []
    for r, m in kin.reversed_moves().items():
        joint, delta = kin.moves()[r]
        nxt, ok = kin.step_array(pos, joint, delta)
        out.append((r, m, kin.flat_index(np.where(ok[:, None], nxt, pos)), ~ok))
    return out


def fill_reversed(tables: np.ndarray, steps: list[tuple[int, int, np.ndarray, np.ndarray]]) -> np.ndarray:
    """Set the rows of the reversed moves of ``tables[m, i, :]`` (a swept table, the mover's
    positions on axis 1) from their forward moves (:func:`reversals`)."""
    for r, m, rows, stop in steps:
        tables[r] = tables[m][rows]
        tables[r][stop] = True
    return tables


class KinematicsArrays:
    """One kinematics' positions as arrays: segments ``S[i]`` (relative to the base) and, per
    computed move (``computed[c]`` is a move index; a reversed move is filled from its forward
    one, :func:`reversals`), the successor ``nxt[c, i]`` (−1 past a hard stop), the turn's
    centre and angle (:meth:`Kinematics.rotation`) and the sweep length.  For
    :func:`batch_swept`: where a move runs into a stop (``stop[c, i]``; ``nxt_or_self`` is
    ``i`` there), the sampled poses ``poses[:, c, i, k]`` (``S_i`` turned by ``k/2**_DEPTH``
    of the move, as coordinates ``px, py, qx, qy``), the turn radii ``r_min``, ``r_max``
    (:func:`.sweep.turn_radii`) and ``slack[c, i, l]`` (:func:`.sweep.turn_slack` of ``2**l``
    pieces)."""

    def __init__(self, kin: Kinematics):
        pos = kin.all_positions()
        self.segments = kin.segments(pos)
        moves = kin.moves()
        self.n_moves = len(moves)
        self.reversals = reversals(kin)
        reversed_ = {r for r, *_ in self.reversals}
        self.computed = [m for m in range(len(moves)) if m not in reversed_]
        if self.computed != list(range(0, len(moves), len(moves) // len(self.computed))):  # moves() order
            raise SupcoordError(f"the batch tables need each joint's two directions in turn, not {moves}")
        self.nxt = np.full((len(self.computed), len(pos)), -1, dtype=np.int64)
        self.centre = np.zeros((len(self.computed), len(pos), 2))
        self.angle = np.zeros((len(self.computed), len(pos)))
        self.length = np.zeros(len(self.computed))
        for c, m in enumerate(self.computed):
            joint, delta = moves[m]
            nxt, ok = kin.step_array(pos, joint, delta)
            idx = np.nonzero(ok)[0]
            self.nxt[c, idx] = kin.flat_index(nxt[idx])
            if len(idx):
                turn_centre, turn_angle = kin.rotation(pos[idx], joint, np.full(len(idx), float(delta)))
                self.centre[c, idx], self.angle[c, idx] = turn_centre, turn_angle
            d = np.zeros(kin.n_joints)
            d[joint] = delta
            self.length[c] = float(kin.sweep_length(d))
        self.turn_samples()

    def empty_table(self, n_other: int) -> tuple[np.ndarray, np.ndarray]:
        """``(W, C)``: an uninitialised swept table of every move ``[m, i, j]`` and the view of
        its computed moves ``C[c] = W[computed[c]]`` (every other move, as
        :meth:`.Kinematics.moves` orders a joint's two directions)."""
        table = np.empty((self.n_moves, self.nxt.shape[1], n_other), dtype=bool)
        return table, table[::self.n_moves // len(self.computed)]

    def table_index(self, flat: np.ndarray, n_other: int) -> np.ndarray:
        """Flat indices into ``C`` (:meth:`empty_table`) as flat indices into ``W``."""
        plane = self.nxt.shape[1] * n_other
        c, rest = np.divmod(flat, plane)
        return np.asarray(self.computed, dtype=np.int64)[c] * plane + rest

    def turn_samples(self) -> None:
        """Compute ``stop``, ``poses``, ``r_min``, ``r_max`` and ``slack`` (class docstring)."""
        self.stop = self.nxt < 0
        self.nxt_or_self = np.where(self.stop, np.arange(self.nxt.shape[1]), self.nxt)
        width = 2 ** _DEPTH
        turn = self.angle[:, :, None] * (np.arange(width + 1) / width)  # (M, P, K)
        centre = self.centre[:, :, None, :]
        ends = [_rotate(self.segments[None, :, None, e, :], centre, turn) for e in (0, 1)]
        self.poses = np.ascontiguousarray(np.moveaxis(np.concatenate(ends, axis=-1), -1, 0))  # (4, C, P, K)
        self.r_min, self.r_max = turn_radii(self.segments[None], self.centre)
        self.slack = np.stack([turn_slack(self.r_max, self.angle, 2 ** level) for level in range(_DEPTH + 1)],
                              axis=-1)


def _buffer(scratch: dict, name: str, shape: tuple, dtype: Any = bool) -> np.ndarray:
    """An array ``scratch[name]`` of ``shape`` and ``dtype``, made once and reused."""
    key = (name, shape, np.dtype(dtype).str)
    if key not in scratch:
        scratch[key] = np.empty(shape, dtype=dtype)
    return scratch[key]


def _prefilter(km: KinematicsArrays, d: np.ndarray, exact: np.ndarray, bsum: float, threshold: float,
               w: np.ndarray, scratch: dict) -> tuple[np.ndarray, ...]:
    """The end-point prefilter of every computed move at once: ``w[c, i, j]`` set True where either
    end pose collides (``d0 < bsum`` or ``d1 < bsum``) or the move runs into a stop; the entries
    left open ``(flat, rows, d0, d1)`` are those neither that nor ``(d0 + d1 − L)/2 ≥ bsum``
    decides.

    With bounds (:func:`_far_bounds`, ``threshold = bsum + max L/2``), only entries with an end
    pose *close* (an exact distance below ``threshold`` + :data:`_BOUND_SLACK`) are looked at:
    elsewhere both ends are at least that far, so ``(d0 + d1 − L)/2 ≥ bsum`` with the slack to
    spare — the entry is free as the exact test would find it."""
    n_moves, n_pos = km.nxt.shape
    n_other = d.shape[1]
    if n_pos * n_other < BOUND_MIN_ENTRIES:  # every distance exact: one dense pass is cheaper
        d1 = d[km.nxt_or_self]  # (C, P, P')
        near = d < bsum
        np.take(near, km.nxt_or_self, axis=0, out=w, mode="clip")
        w |= near
        w |= km.stop[:, :, None]
        lower = np.add(d, d1)
        lower -= km.length[:, None, None]
        decided = lower >= 2 * bsum
        decided |= w
        flat = np.flatnonzero(~decided)
        row = flat // n_other
        return flat, row, d.reshape(-1)[flat % d.size], d1.reshape(-1)[flat]
    # the intermediate tables reuse ``scratch`` (fresh ones cost memory maps and page faults)
    hit = np.less(d, bsum, out=_buffer(scratch, "hit", d.shape))  # exact where it holds: bounds are not below
    np.take(hit, km.nxt_or_self, axis=0, out=w, mode="clip")  # (C, P, P')
    w |= hit
    w |= km.stop[:, :, None]
    close = np.less(d, threshold + _BOUND_SLACK, out=_buffer(scratch, "close", d.shape))
    close &= exact
    cand = np.take(close, km.nxt_or_self, axis=0, out=_buffer(scratch, "cand", w.shape), mode="clip")
    cand |= close
    np.greater(cand, w, out=cand)  # cand and not w
    flat = np.flatnonzero(cand)
    row, j = np.divmod(flat, n_other)
    m, i = np.divmod(row, n_pos)
    e0 = d[i, j]
    e1 = d[km.nxt_or_self[m, i], j]
    lower = np.add(e0, e1)  # d0 + d1 − L ≥ 2·bsum is (d0 + d1 − L)/2 ≥ bsum: halving is exact
    lower -= km.length[m]
    keep = lower < 2 * bsum
    return flat[keep], row[keep], e0[keep], e1[keep]


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
    cm, cs = segment_coords(seg_m), segment_coords(seg_s)[:, jr]
    e0[r] = segment_distance_xy(*cm[:, i[r]], *cs)
    e1[r] = segment_distance_xy(*cm[:, i1[r]], *cs)
    lower = np.add(e0, e1)
    lower -= km.length[row // seg_m.shape[0]]
    keep = lower < 2 * bsum
    return flat[keep], row[keep], e0[keep], e1[keep]


class _OpenEntries:
    """The entries of a chunk's tables that neither end pose nor the bound over the whole turn
    decides, gathered for :meth:`decide`: per table its flat indices (into the table of every
    move), rows ``c·P + i`` (``c`` a computed move), columns ``j`` and end distances ``d0``,
    ``d1``; the turn data of each distinct kinematics (mover's frame) and each table's
    segments, in blocks, with where each table's data begin."""

    def __init__(self) -> None:
        self.jobs: list[tuple[np.ndarray, np.ndarray]] = []
        self.rows, self.cols, self.d0s, self.d1s, self.counts, self.heights, self.bsums = [], [], [], [], [], [], []
        self.at_kin, self.at_mover, self.at_turn, self.at_other = [], [], [], []
        self.kin_at: dict[int, int] = {}
        self.kins: list[KinematicsArrays] = []
        self.movers, self.centres, self.angles, self.others, self.frames = [], [], [], [], []
        self.n_kin = self.n_mover = self.n_turn = self.n_other = 0

    def add(self, table: np.ndarray, km: KinematicsArrays, seg_m: np.ndarray, seg_s: np.ndarray, shift: Any,
            bsum: float, flat: np.ndarray, row: np.ndarray, e0: np.ndarray, e1: np.ndarray) -> None:
        """Table ``table`` of mover ``km`` (segments ``seg_m``) past ``seg_s`` (``shift``: the
        mover's base), with the open entries of its computed moves (:func:`_exact_ends`)."""
        n_pos, n_other_pos = len(seg_m), len(seg_s)
        if len(flat):
            # the sampled bound over the whole turn (level 0 of sweep.bisect_turns)
            keep = (e0 + e1) * 0.5 - km.slack.reshape(-1, _DEPTH + 1)[row, 0] < bsum + MARGIN
            if keep.any():
                if id(km) not in self.kin_at:
                    self.kin_at[id(km)] = self.n_kin
                    self.kins.append(km)
                    self.n_kin += km.slack.shape[0] * n_pos
                flat = flat[keep]
                self.jobs.append((table, km.table_index(flat, n_other_pos)))
                self.cols.append(flat % n_other_pos)
                self.rows.append(row[keep])
                self.d0s.append(e0[keep])
                self.d1s.append(e1[keep])
                self.counts.append(int(np.count_nonzero(keep)))
                self.heights.append(n_pos)
                self.bsums.append(bsum)
                self.at_kin.append(self.kin_at[id(km)])
                self.at_mover.append(self.n_mover)
                self.at_turn.append(self.n_turn)
                self.at_other.append(self.n_other)
        self.movers.append(seg_m)
        self.centres.append((km.centre + shift).reshape(-1, 2))
        self.angles.append(km.angle.reshape(-1))
        self.others.append(seg_s)
        self.frames.append((seg_s - shift).reshape(-1, 4))  # the standing segments in the mover's frame
        self.n_mover += n_pos
        self.n_turn += len(km.nxt) * n_pos
        self.n_other += n_other_pos

    def decide(self) -> None:
        """The annulus, the bisected turn, then the closed form, over the open entries of every
        table, :data:`DECIDE_BLOCK` at a time; the collisions are set in their tables."""
        if not self.jobs:
            return
        counts = np.asarray(self.counts)

        def spread(values: list) -> np.ndarray:
            return np.repeat(np.asarray(values), counts)

        row = np.concatenate(self.rows)
        d0, d1 = np.concatenate(self.d0s), np.concatenate(self.d1s)
        bsum = spread(self.bsums)
        krow = spread(self.at_kin) + row
        ocol = spread(self.at_other) + np.concatenate(self.cols)
        trow = spread(self.at_turn) + row
        mrow = spread(self.at_mover) + row % spread(self.heights)
        kins = self.kins
        r_min = np.concatenate([k.r_min.reshape(-1) for k in kins])
        r_max = np.concatenate([k.r_max.reshape(-1) for k in kins])
        centre = np.concatenate([k.centre.reshape(-1, 2) for k in kins])
        poses = np.concatenate([k.poses.reshape(4, -1, 2 ** _DEPTH + 1) for k in kins], axis=1)
        slack = np.concatenate([k.slack.reshape(-1, _DEPTH + 1) for k in kins])
        frame = np.concatenate(self.frames)
        frame_xy = np.ascontiguousarray(frame.T)
        movers, centres = np.concatenate(self.movers), np.concatenate(self.centres)
        angles, others = np.concatenate(self.angles), np.concatenate(self.others)
        result = np.zeros(len(d0), dtype=bool)
        for lo in range(0, len(d0), DECIDE_BLOCK):
            e = slice(lo, lo + DECIDE_BLOCK)
            # the annulus, then the bisected turn, in the mover's frame
            kr, oc = krow[e], ocol[e]
            todo = np.nonzero(~annulus_clear(centre[kr], r_min[kr], r_max[kr], frame[oc].reshape(-1, 2, 2), bsum[e]))[0]
            kr, oc = kr[todo], oc[todo]

            def pose_distance(t: np.ndarray, k: np.ndarray, kr: np.ndarray = kr, oc: np.ndarray = oc) -> np.ndarray:
                return segment_distance_xy(*poses[:, kr[t], k], *frame_xy[:, oc[t]])

            hit, open_ = bisect_turns(d0[e][todo], d1[e][todo], slack[kr], bsum[e][todo], pose_distance, _DEPTH)
            result[lo + todo[hit]] = True
            exact = lo + todo[open_]
            if len(exact):  # the closed form, on the very numbers the tables always used
                clearance = rotation_clearance(movers[mrow[exact]], centres[trow[exact]], angles[trow[exact]],
                                               others[ocol[exact]])
                result[exact] = clearance < bsum[exact]
        at = 0  # the open entries are False so far: set the collisions
        for (w, f), n in zip(self.jobs, counts):
            w.reshape(-1)[f[result[at:at + n]]] = True
            at += n


def batch_swept(arrays_a: list[KinematicsArrays], arrays_b: list[KinematicsArrays], offsets: Any,
                bsums: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``[(T, W0, W1), …]`` for pairs ``k`` with ``a`` at the origin and ``b`` at ``offsets[k]``:
    the static table ``T[i, j] = D[i, j] < bsum`` and the swept tables of ``a`` moving
    (``W0[m, i, j]``) and of ``b`` moving, in ``b``'s rows (``W1[m, j, i]``), as
    :func:`.collision.swept_table` defines them.  Only the computed moves are decided
    (:class:`KinematicsArrays`); the reversed ones are filled from them at the end."""
    offsets = np.asarray(offsets, float).reshape(-1, 2)
    computed: list[tuple[np.ndarray, np.ndarray, KinematicsArrays, np.ndarray, KinematicsArrays]] = []
    open_entries = _OpenEntries()
    scratch: dict = {}
    for ka, kb, off, bsum in zip(arrays_a, arrays_b, offsets, np.asarray(bsums, float)):
        sa, sb = ka.segments, kb.segments + off
        # exact where either end pose could be near or the end-point bound could fail
        threshold = bsum + max(ka.length.max(initial=0.0), kb.length.max(initial=0.0)) / 2
        dist, known, dist_t, known_t = _far_bounds(sa, sb, threshold, scratch)
        tables = []
        for km, seg_m, seg_s, shift, d, exact in ((ka, sa, sb, 0.0, dist, known),
                                                  (kb, sb, sa, off, dist_t, known_t)):
            table, w = km.empty_table(len(seg_s))
            flat, row, e0, e1 = _prefilter(km, d, exact, bsum, threshold, w, scratch)
            if len(flat):
                flat, row, e0, e1 = _exact_ends(flat, row, e0, e1, exact, km, seg_m, seg_s, bsum)
            open_entries.add(table, km, seg_m, seg_s, shift, bsum, flat, row, e0, e1)
            tables.append((table, km))
        computed.append((dist < bsum, tables[0], tables[1]))
    open_entries.decide()  # then the reversed moves, from the decided computed ones
    return [(static, fill_reversed(wa, ka.reversals), fill_reversed(wb, kb.reversals))
            for static, (wa, ka), (wb, kb) in computed]
