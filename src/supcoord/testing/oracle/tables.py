"""The oracle's collision tables of one pair of positioners, three-valued.

For positioners ``a`` (base ``x_a``, arm ``A``) and ``b`` (base ``x_b``, arm ``B``: the same
arm, or each its own lattice), write ``o = x_b − x_a`` and ``r = r_a + r_b (+ margin)``;
``S_a(q)``, ``S_b(q)`` are the colliding segments relative to the bases
(:class:`.oracle_model.Arm`).  Everything is computed in ``a``'s frame:

- **static** ``T[i, j] = dist(S_a(i), o + S_b(j)) < r`` (plain evaluation, no motion; a
  distance within :data:`.certified_sweep.TIE` of ``r`` is a tie, :meth:`PairTables.static_state`);
- **edges** of the single-move semantics: ``E[side][k][i, j]`` — the mover (``a`` when
  ``side = 0``, moving from ``i``; ``b`` when ``side = 1``, moving from ``j``) turns joint
  ``k`` by ``+1`` while the other stands still.  The move ``−1`` from ``i'`` traces the
  same poses as ``+1`` from ``step(i', k, −1)``, so it reads the same entry: the
  oracle's moves are symmetric by construction, not by symmetrising;
- **simultaneous** ``M[u, v, i, j]``: ``a`` moves by the joint deltas ``opts[u]`` from ``i``
  while ``b`` moves by ``opts[v]`` from ``j`` (both linear in joint space, one time ``t``).

Swept entries are ``FREE``, ``HIT`` or ``UNDECIDED`` (:func:`.certified_sweep.certify`, seeded with
the static distances at both ends).  An entry the branch and bound leaves undecided
whose motion is one joint of one positioner (a rigid turn) is then decided at its
critical times (:mod:`.rotation`), unless that least distance is a tie.  What stays
undecided (ties; several joints moving within 10⁻⁹ mm of ``r``) is counted in
:attr:`PairTables.counts` and left to :mod:`.bfs`.  Entries of moves past a hard stop
are ``HIT`` and never read.  A pair whose bases are farther apart than ``reach_a + reach_b + r`` (with
10⁻⁹ mm to spare) never collides: :meth:`PairTables.far` and no table is built.
"""

from __future__ import annotations

import numpy as np

from .distance import segment_gap
from .oracle_model import Arm
from .rotation import critical_times
from .certified_sweep import HIT, TIE, UNDECIDED, certify, classify

__all__ = ["PairTables", "joint_options"]


def joint_options(arm: Arm) -> np.ndarray:
    """Per-step joint deltas of one positioner, ``{−1, 0, +1}^J`` with standing still first."""
    grids = np.meshgrid(*([np.array([0, 1, -1])] * arm.n_joints), indexing="ij")
    return np.stack([g.ravel() for g in grids], axis=-1).astype(np.int64)


class PairTables:
    """Tables of one pair geometry ``(arm, o, r, arm_b)`` (module docstring), computed on
    demand; ``arm_b`` (default ``arm``) is ``b``'s arm, with the same joints and steps."""

    def __init__(self, arm: Arm, offset: complex, need: float, arm_b: Arm | None = None):
        self.arm, self.offset, self.need = arm, complex(offset), float(need)
        self.arm_b = arm if arm_b is None else arm_b
        if (self.arm_b.steps, self.arm_b.wraps) != (arm.steps, arm.wraps):
            raise ValueError("the two arms of a pair must have the same joints and steps")
        self.pos = arm.positions()
        self._seg = arm.segment(self.pos)
        self._seg_b = self._seg if self.arm_b is arm else self.arm_b.segment(self.pos)
        self._static: np.ndarray | None = None
        self._edges: dict[tuple[int, int], np.ndarray] = {}
        self._simultaneous: np.ndarray | None = None
        #: swept entries: decided by bound and bisection, at critical times, left undecided
        self.counts = {"bisection": 0, "critical_times": 0, "undecided": 0}

    @property
    def far(self) -> bool:
        return abs(self.offset) > self.arm.reach + self.arm_b.reach + self.need + 1e-9

    def static_gap(self) -> np.ndarray:
        """``dist(S_a(i), o + S_b(j))`` for every ``(i, j)``."""
        if self._static is None:
            (p0, p1), (q0, q1), o = self._seg, self._seg_b, self.offset
            self._static = segment_gap(p0[:, None], p1[:, None], o + q0[None, :], o + q1[None, :])
        return self._static

    def static(self) -> np.ndarray:
        """Colliding configurations (ties excluded)."""
        return self.static_gap() < self.need - TIE

    def static_state(self) -> np.ndarray:
        """``FREE``/``HIT``/``UNDECIDED`` (a tie) of every ``(i, j)``."""
        return classify(self.static_gap(), np.full_like(self.static_gap(), self.need))

    def motion(self, qa: np.ndarray, da: np.ndarray, qb: np.ndarray, db: np.ndarray, d0: np.ndarray,
                d1: np.ndarray) -> np.ndarray:
        """Three-valued verdicts of the motions ``a: qa + t·da``, ``b: qb + t·db`` (rows)."""
        arm, arm_b, o = self.arm, self.arm_b, self.offset
        qa, qb = qa.astype(float), qb.astype(float)
        da, db = da.astype(float), db.astype(float)

        def gap(e: np.ndarray, t: np.ndarray) -> np.ndarray:
            a0, a1 = arm.segment(qa[e] + t[:, None] * da[e])
            b0, b1 = arm_b.segment(qb[e] + t[:, None] * db[e])
            return segment_gap(a0, a1, o + b0, o + b1)

        lip = arm.speed(da) + arm_b.speed(db)
        out = certify(gap, lip, np.full(len(qa), self.need), d0, d1)
        open_ = np.nonzero(out == UNDECIDED)[0]
        moving = (da != 0).sum(axis=1) + (db != 0).sum(axis=1)
        turn = open_[moving[open_] == 1]
        if len(turn):
            least = self.least_on_turn(qa[turn], da[turn], qb[turn], db[turn])
            out[turn] = classify(least, np.full(len(turn), self.need))
        self.counts["bisection"] += len(out) - len(open_)
        self.counts["critical_times"] += int((out[turn] != UNDECIDED).sum())
        self.counts["undecided"] += int((out == UNDECIDED).sum())
        return out

    def least_on_turn(self, qa: np.ndarray, da: np.ndarray, qb: np.ndarray, db: np.ndarray) -> np.ndarray:
        """Exact ``min_t d(t)`` of single-joint motions of one member (:mod:`.rotation`)."""
        arm, arm_b, o = self.arm, self.arm_b, self.offset
        qa, qb = np.asarray(qa, dtype=float), np.asarray(qb, dtype=float)
        a_moves = np.any(da != 0, axis=1)
        q_mov, d_mov = np.where(a_moves[:, None], qa, qb), np.where(a_moves[:, None], da, db)
        q_still = np.where(a_moves[:, None], qb, qa)
        shift = np.where(a_moves, 0, o)  # the mover's base in a's frame
        joint = np.argmax(d_mov != 0, axis=1)
        step = d_mov[np.arange(len(joint)), joint]
        centre = np.array([shift[e] + (arm if a_moves[e] else arm_b).pivot(q_mov[e], int(joint[e]))
                           for e in range(len(joint))])
        if arm_b is arm:
            angle = arm.turn(q_mov, joint, step)
            m0, m1 = arm.segment(q_mov)
            s0, s1 = arm.segment(q_still)
        else:  # the mover's own lattice and segment, the other's for the one standing still
            w = a_moves[:, None]
            angle = np.where(a_moves, arm.turn(q_mov, joint, step), arm_b.turn(q_mov, joint, step))
            (ma0, ma1), (mb0, mb1) = arm.segment(q_mov), arm_b.segment(q_mov)
            (sa0, sa1), (sb0, sb1) = arm.segment(q_still), arm_b.segment(q_still)
            m0, m1 = np.where(w[:, 0], ma0, mb0), np.where(w[:, 0], ma1, mb1)
            s0, s1 = np.where(w[:, 0], sb0, sa0), np.where(w[:, 0], sb1, sa1)
        other = np.where(a_moves, o, 0)
        times = critical_times(centre, angle, shift + m0, shift + m1, other + s0, other + s1)
        k = times.shape[1]
        rows = np.repeat(np.arange(len(qa)), k)
        t = times.ravel()[:, None]
        a0, a1 = arm.segment(qa[rows] + t * da[rows])
        b0, b1 = arm_b.segment(qb[rows] + t * db[rows])
        return segment_gap(a0, a1, o + b0, o + b1).reshape(len(qa), k).min(axis=1)

    def edge(self, side: int, joint: int) -> np.ndarray:
        """``E[side][joint]`` (module docstring) as an ``(n, n)`` uint8 array over ``(i, j)``."""
        key = (side, joint)
        if key not in self._edges:
            n = len(self.pos)
            delta = np.zeros((1, self.arm.n_joints), dtype=np.int64)
            delta[0, joint] = 1
            nxt = self.arm.successors(delta)[0]
            g = self.static_gap()
            ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
            ii, jj = ii.ravel(), jj.ravel()
            out = np.full(n * n, HIT, dtype=np.uint8)
            if side == 0:
                ok = nxt[ii] >= 0
                mover, other = ii[ok], jj[ok]
                d1 = g[nxt[mover], other]
                still = np.zeros((len(mover), self.arm.n_joints), dtype=np.int64)
                moving = np.broadcast_to(delta, still.shape)
                out[ok] = self.motion(self.pos[mover], moving, self.pos[other], still, g[mover, other], d1)
            else:
                ok = nxt[jj] >= 0
                other, mover = ii[ok], jj[ok]
                d1 = g[other, nxt[mover]]
                still = np.zeros((len(mover), self.arm.n_joints), dtype=np.int64)
                moving = np.broadcast_to(delta, still.shape)
                out[ok] = self.motion(self.pos[other], still, self.pos[mover], moving, g[other, mover], d1)
            self._edges[key] = out.reshape(n, n)
        return self._edges[key]

    def simultaneous(self) -> np.ndarray:
        """``M[u, v, i, j]`` over :func:`joint_options` (module docstring), uint8."""
        if self._simultaneous is None:
            opts = joint_options(self.arm)
            nxt = self.arm.successors(opts)
            n, k = len(self.pos), len(opts)
            g = self.static_gap()
            out = np.full((k, k, n, n), HIT, dtype=np.uint8)
            ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
            ii, jj = ii.ravel(), jj.ravel()
            for u in range(k):
                for v in range(k):
                    ok = (nxt[u, ii] >= 0) & (nxt[v, jj] >= 0)
                    i, j = ii[ok], jj[ok]
                    da = np.broadcast_to(opts[u], (len(i), self.arm.n_joints))
                    db = np.broadcast_to(opts[v], (len(j), self.arm.n_joints))
                    block = out[u, v].reshape(-1)
                    block[ok] = self.motion(self.pos[i], da, self.pos[j], db, g[i, j], g[nxt[u, i], nxt[v, j]])
            self._simultaneous = out
        return self._simultaneous
