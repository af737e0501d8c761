"""Greedy simultaneous descent: every unfinished positioner steps towards its target at once.

One *descent step* from a configuration ``c`` chooses, positioner by positioner in
priority order (smaller number first, then index), a set ``M_p`` of single-joint moves
towards ``p``'s target (every joint that is off target, one step the short way round;
if that set is refused, each joint alone; at half a turn both ways are tried) and
keeps the first that is *compatible* with the choices made so far:

1. **serialisable in any order** — for every neighbour pair ``(p, q)`` that can block
   a move (:func:`.guards.conflict_graph`), every move ``μ = (p, m) ∈ M_p`` is
   allowed by the symmetrised swept table ``B`` from every pose ``p`` can have when
   ``μ`` starts (its other moves of the step done or not) against every pose of ``q``
   (any subset of ``M_q`` done), and the same with ``p`` and ``q`` exchanged::

       ∀ μ ∈ M_p, A ⊆ M_p \\ {μ}, A' ⊆ M_q.   ¬B_{p,m}(c_p + A, c_q + A')

   Guards are conjunctions over pairs, so then *every* ordering of the step's moves is
   a valid single-move sequence of the guarded model (:mod:`.model`);
2. **collision-free when merged** — for every neighbour pair (:attr:`Problem.pairs`)
   in which both move, or one moves two joints, the simultaneous motion
   ``c + t·Δ`` is free (:func:`supcoord.geometry.chain_motion.chain_motion_collides`, cached: :func:`motion_free`).

Steps repeat until every positioner is at target or a step chooses nothing (a stall).
Each step strictly lowers ``Σ_p Σ_j d_j(c_p, target_p)``, so the descent ends.

**Why it keeps the planner exact.**  By (1) the descent is a sequence of single moves
of the guarded model, so the configuration ``c*`` it ends in is reachable from the
start in the single-move graph; the graph is undirected, hence the target is
reachable from ``c*`` iff from the start, and the exact symbolic windows of
:mod:`.windows` may continue from ``c*`` without changing any verdict.  By (2)
and the swept tables, each step is collision-free as executed simultaneously.  The
descent never answers "infeasible"; it only shortens the exact search and the plan.

References
----------
- C. Sayres et al., kaiju: SDSS-V robots move greedily towards target while the
  motion is free (here: with the serialisability condition that keeps exactness).
- E. F. Moore 1959 / the single-move model of ``docs/formats.md``.
"""

from __future__ import annotations

import itertools
from typing import Callable, Sequence

import numpy as np

from ..geometry.chain_motion import chain_geometry, chain_motion_collides
from ..geometry.collision import DEFAULT_TOL
from ..problems.plan import Move
from ..problems.problem import Problem
from .caches import caches_for
from .guards import blocked_bits, blocked_entries, blocked_lookup, conflict_graph, pair_graph

__all__ = ["descent", "descent_step", "wanted_moves", "motion_free", "MotionChecker"]


def wanted_moves(problem: Problem, c: np.ndarray, p: int) -> list[list[tuple[int, int]]]:
    """Candidate move sets of ``p`` towards its target, most ambitious first."""
    per_joint = [[(j, d) for d in ds]
                 for j, ds in enumerate(problem.kinematics.directions(c[p], problem.target[p])) if ds]
    out: list[list[tuple[int, int]]] = []
    if len(per_joint) > 1:
        out.extend([list(combo) for combo in itertools.product(*per_joint)])
    for options in per_joint:
        out.extend([[mv] for mv in options])
    return out


def motion_free(problem: Problem, k: int, side: int, x: np.ndarray, dp: np.ndarray, y: np.ndarray,
                dq: np.ndarray | None, tol: float = DEFAULT_TOL) -> bool:
    """Is the simultaneous motion of pair ``k`` free: the member ``side`` moving ``x → x + dp``,
    the other ``y → y + dq`` (None: standing)?  :func:`~supcoord.geometry.chain_motion.chain_motion_collides`
    (one motion on floats), cached per (pair geometry, poses, deltas): a grid has few distinct
    pair offsets (held in the problem's :class:`~supcoord.planning.caches.PlanningCache`)."""
    dq = (0,) * problem.kinematics.n_joints if dq is None else _ints(dq)
    return not _motion_hit(problem, caches_for(problem).motions, k, side, _ints(x), _ints(dp), _ints(y), dq, tol)


class MotionChecker:
    """:func:`motion_free` for many queries on one problem: the problem's cache and each pair's
    geometry key looked up once (the schedules ask tens of thousands of times)."""

    def __init__(self, problem: Problem, tol: float = DEFAULT_TOL):
        self.problem, self.tol = problem, tol
        self.motions = caches_for(problem).motions
        self.standing = (0,) * problem.kinematics.n_joints
        self._pairs: dict[int, tuple[tuple, tuple]] = {}  # pair -> (geometry key, _pair_arguments)

    def free(self, k: int, side: int, x: np.ndarray, dp: np.ndarray, y: np.ndarray, dq: np.ndarray | None) -> bool:
        """``motion_free(problem, k, side, x, dp, y, dq, tol)``."""
        pair = self._pairs.get(k)
        if pair is None:
            pair = self._pairs[k] = (self.problem.pair_geometry_key(k), _pair_arguments(self.problem, k))
        return not _motion_hit(self.problem, self.motions, k, side, _ints(x), _ints(dp), _ints(y),
                               self.standing if dq is None else _ints(dq), self.tol, *pair)


def _ints(v: Sequence[int] | np.ndarray) -> tuple[int, ...]:
    """``v`` as a tuple of Python ints (a key part of :func:`_motion_hit`)."""
    return tuple(v.tolist()) if isinstance(v, np.ndarray) else tuple(int(u) for u in v)


def _motion_hit(problem: Problem, cache: dict, k: int, side: int, x: tuple[int, ...], dx: tuple[int, ...],
                y: tuple[int, ...], dy: tuple[int, ...], tol: float, geometry: tuple | None = None,
                pair: tuple | None = None) -> bool:
    """:func:`motion_free`'s verdict negated, on poses and deltas given as tuples of ints, read
    from or written to ``cache`` (the problem's ``PlanningCache.motions``); ``geometry``: the
    pair's :meth:`Problem.pair_geometry_key` and ``pair`` its :func:`_pair_arguments`, when the
    caller has them."""
    key = (problem.pair_geometry_key(k) if geometry is None else geometry) + \
        ((x, dx, y, dy) if side == 0 else (y, dy, x, dx))
    hit = cache.get(key)
    if hit is None:
        geo_a, base_a, geo_b, base_b, bsum = _pair_arguments(problem, k) if pair is None else pair
        hit = cache[key] = chain_motion_collides(geo_a, base_a, key[-4], key[-3], geo_b, base_b, key[-2], key[-1],
                                                 bsum, tol)
    return hit


def _pair_arguments(problem: Problem, k: int) -> tuple:
    """``(geo_a, base_a, geo_b, base_b, bsum)`` of pair ``k``: :func:`chain_motion_collides`'s
    arguments but the poses (bases as tuples of floats, the buffer sum as a float)."""
    a, b = (int(v) for v in problem.pairs[k])
    return (chain_geometry(problem.kin(a)), tuple(map(float, problem.bases[a])), chain_geometry(problem.kin(b)),
            tuple(map(float, problem.bases[b])), float(problem.buffers[a] + problem.buffers[b]))


class _Lookups:
    """Per-problem lookups: moves, conflict adjacency, pair adjacency, and memos of what the
    descent steps read again and again (flat poses part-way through a move set, blocked tables
    as bytes)."""

    def __init__(self, problem: Problem):
        kin = problem.kinematics
        self.problem = problem
        self.kin = kin
        self.moves = kin.moves()
        self.move_index = {mv: i for i, mv in enumerate(self.moves)}
        self.adj = conflict_graph(problem)
        self.pair_adj = pair_graph(problem)
        self.lazy = problem.tables().lazy  # entries decided as read (guards.blocked_entries)
        self.lookup = blocked_lookup(problem) if self.lazy else None
        self.motions = caches_for(problem).motions  # motion_free's verdicts

        self.steps = [j.steps for j in kin.joints]
        self.wraps = [j.wraps for j in kin.joints]
        self.strides = [int(v) for v in kin._strides]
        self._starts: dict[tuple, list[tuple[int, list[int]]]] = {}
        self._poses: dict[tuple, list[int]] = {}
        self._bytes: dict[tuple, tuple[memoryview, int, int]] = {}
        self._rows: dict[tuple, dict[int, int]] = {}  # table_rows()
        self._masks: dict[tuple, int] = {}  # pose_mask()
        self.targets = [tuple(row) for row in problem.target.tolist()]
        self._wanted: dict[tuple[tuple[int, ...], tuple[int, ...]], list[list[tuple[int, int]]]] = {}
        self._geometry: dict[int, tuple] = {}
        self._pairs: dict[int, tuple] = {}
        self._own: dict[tuple, bool] = {}

    def wanted(self, c: np.ndarray, cp: tuple[int, ...], p: int) -> list[list[tuple[int, int]]]:
        """:func:`wanted_moves` of ``p`` at ``c`` (``cp``: ``c[p]`` as a tuple), memoised by ``c[p]``
        and ``p``'s target (all it depends on: robots share the lattice)."""
        key = (cp, self.targets[p])
        out = self._wanted.get(key)
        if out is None:
            out = self._wanted[key] = wanted_moves(self.problem, c, p)
        return out

    def own_blocked(self, p: int, cp: tuple[int, ...], d: tuple[int, ...], tol: float) -> bool:
        """:meth:`Problem.own_motion_blocked` of one motion, memoised by ``(p, cp, d, tol)``."""
        key = (p, cp, d, tol)
        out = self._own.get(key)
        if out is None:
            out = self._own[key] = bool(self.problem.own_motion_blocked(p, cp, d, tol)[0])
        return out

    def geometry(self, k: int) -> tuple:
        """:meth:`Problem.pair_geometry_key` of pair ``k``, memoised."""
        out = self._geometry.get(k)
        if out is None:
            out = self._geometry[k] = self.problem.pair_geometry_key(k)
        return out

    def pair(self, k: int) -> tuple:
        """:func:`_pair_arguments` of pair ``k``, memoised."""
        out = self._pairs.get(k)
        if out is None:
            out = self._pairs[k] = _pair_arguments(self.problem, k)
        return out

    def pose(self, q: np.ndarray, ms: Sequence[tuple[int, int]]) -> np.ndarray:
        out = q.copy()
        for j, d in ms:
            out[j] += d
        return self.kin.wrap(out)

    def flat_after(self, q: Sequence[int], ms: Sequence[tuple[int, int]]) -> int:
        """:meth:`Kinematics.flat_position` of ``q`` after the moves ``ms`` (Python ints: called
        for every subset of every candidate of every step)."""
        v = list(q)
        for j, d in ms:
            v[j] += d
        return sum((x % n if w else x) * st for x, n, w, st in zip(v, self.steps, self.wraps, self.strides))

    def starts(self, cp: tuple[int, ...], mp: Sequence[tuple[int, int]]) -> list[tuple[int, list[int]]]:
        """``[(move, [flat poses it may start from]), …]`` for each move of ``mp`` from ``cp``
        (its other moves done or not), memoised by ``(cp, mp)``."""
        key = (cp, tuple(mp))
        out = self._starts.get(key)
        if out is None:
            out = self._starts[key] = [(self.move_index[mv], [self.flat_after(cp, s)
                                                              for s in _subsets([x for x in mp if x != mv])])
                                       for mv in mp]
        return out

    def poses(self, cq: tuple[int, ...], mq: Sequence[tuple[int, int]]) -> list[int]:
        """The flat poses of ``cq`` after every subset of ``mq``, memoised by ``(cq, mq)``."""
        key = (cq, tuple(mq))
        out = self._poses.get(key)
        if out is None:
            out = self._poses[key] = [self.flat_after(cq, s) for s in _subsets(mq)]
        return out

    def table_bytes(self, k: int, side: int) -> tuple[memoryview, int, int]:
        """``(buf, row, width)``: :func:`.guards.blocked_bits` of ``(k, side)`` as a flat view of
        bytes (no copy), entry ``B[m, i, j]`` bit ``7 − j % 8`` of ``buf[m·row + i·width + j // 8]``;
        one per pair geometry, like the tables."""
        key = self.geometry(k) + (side,)
        out = self._bytes.get(key)
        if out is None:
            bits = blocked_bits(self.problem, k, side)
            flat = memoryview(np.ascontiguousarray(bits).reshape(-1))
            out = self._bytes[key] = (flat, bits.shape[1] * bits.shape[2], bits.shape[2])
        return out

    def table_rows(self, k: int, side: int) -> dict[int, int]:
        """Rows ``B[m, i, :]`` of :meth:`table_bytes` read so far as Python ints (big-endian, so
        entry ``j`` is bit ``8·width − 1 − j``), by their offset ``m·row + i·width``; one per pair
        geometry, like the tables."""
        key = self.geometry(k) + (side,)
        out = self._rows.get(key)
        if out is None:
            out = self._rows[key] = {}
        return out

    def pose_mask(self, cq: tuple[int, ...], mq: Sequence[tuple[int, int]], width: int) -> int:
        """The bits of :meth:`poses` ``(cq, mq)`` in a row of :meth:`table_rows` of ``width`` bytes,
        memoised."""
        key = (cq, tuple(mq), width)
        out = self._masks.get(key)
        if out is None:
            top = 8 * width - 1
            out = self._masks[key] = sum({1 << (top - j) for j in self.poses(cq, mq)})
        return out

    def delta(self, ms: Sequence[tuple[int, int]]) -> tuple[int, ...]:
        """The joint delta of the moves ``ms`` as a tuple of ints."""
        d = [0] * len(self.steps)
        for j, v in ms:
            d[j] += v
        return tuple(d)


def _subsets(ms: Sequence[tuple[int, int]]) -> list[list[tuple[int, int]]]:
    return [list(s) for r in range(len(ms) + 1) for s in itertools.combinations(ms, r)]


def _serialisable(T: _Lookups, k: int, side: int, cp: tuple[int, ...], mp: list, cq: tuple[int, ...],
                  mq: list) -> bool:
    """Condition (1) for the moves ``mp`` of the pair member ``side`` (at ``cp``) against ``mq``
    (from ``cq``)."""
    starts, js = T.starts(cp, mp), T.poses(cq, mq)
    if T.lazy:  # entries decided ahead by _prefetch; any other is decided here
        mm, ii, jj = [], [], []
        for m, flats in starts:
            for i in flats:
                for j in js:
                    hit = T.lookup(k, side, m, i, j)
                    if hit:
                        return False
                    if hit is None:
                        mm.append(m)
                        ii.append(i)
                        jj.append(j)
        return not mm or not blocked_entries(T.problem, k, side, mm, ii, jj).any()
    buf, row, width = T.table_bytes(k, side)
    rows, mask = T.table_rows(k, side), T.pose_mask(cq, mq, width)
    for m, flats in starts:
        for i in flats:
            at = m * row + i * width
            bits = rows.get(at)
            if bits is None:
                bits = rows[at] = int.from_bytes(buf[at:at + width], "big")
            if bits & mask:
                return False
    return True


def _compatible(T: _Lookups, c: Sequence[tuple[int, ...]], chosen: dict[int, list], p: int, mp: list,
                tol: float) -> bool:
    """Conditions (1) and (2) of the module docstring for ``p``'s moves ``mp`` from the
    configuration ``c`` (a tuple of ints per positioner) beside the moves ``chosen``."""
    problem = T.problem
    if len(mp) > 1 or not T.adj[p]:  # several joints at once, or no neighbour table holds them: its own constraints
        if T.own_blocked(p, c[p], T.delta(mp), tol):
            return False
    for k, q, side in T.adj[p]:  # (1): both orders, every subset
        mq = chosen.get(q, [])
        if not _serialisable(T, k, side, c[p], mp, c[q], mq):
            return False
        if mq and not _serialisable(T, k, 1 - side, c[q], mq, c[p], mp):
            return False
    dp = None
    for k, q, side in T.pair_adj[p]:  # (2): merged motion of the pair
        mq = chosen.get(q, [])
        if not mq and len(mp) < 2:
            continue  # one joint against a standing neighbour: the swept table of (1)
        dp = T.delta(mp) if dp is None else dp
        if _motion_hit(problem, T.motions, k, side, c[p], dp, c[q], T.delta(mq), tol, T.geometry(k), T.pair(k)):
            return False
    return True


def descent_step(problem: Problem, c: np.ndarray, T: _Lookups | None = None,
                 tol: float = DEFAULT_TOL) -> list[Move]:
    """The moves of one descent step from ``c`` (empty: a stall), in priority order."""
    T = T or _Lookups(problem)
    todo = np.nonzero((c != problem.target).any(axis=1))[0].tolist()
    todo.sort(key=lambda p: (problem.priority[p], p))
    ct = [tuple(row) for row in c.tolist()]
    if T.lazy:
        _prefetch(T, c, todo, ct)
    chosen: dict[int, list] = {}
    for p in todo:
        for mp in T.wanted(c, ct[p], p):
            if _compatible(T, ct, chosen, p, mp, tol):
                chosen[p] = mp
                break
    return [(p, j, d) for p in todo if p in chosen for j, d in chosen[p]]


def _prefetch(T: _Lookups, c: np.ndarray, todo: list[int], ct: list[tuple[int, ...]]) -> None:
    """Decide at once (:func:`.guards.blocked_entries`) every lazy table entry that
    condition (1) may read in this step: each unfinished positioner's candidate moves from its
    poses part-way through a candidate set, against each neighbour's poses part-way through
    one of its own (a superset of what the step reads, in one vectorised call instead of
    thousands of small ones)."""
    cand = {p: T.wanted(c, ct[p], p) for p in todo}
    poses: dict[int, list[int]] = {}  # q -> flat poses part-way through its candidates
    starts: dict[int, set[tuple[int, int]]] = {}  # p -> (move, flat pose it starts from)
    for p in todo:
        cp = c[p].tolist()
        got = {T.flat_after(cp, [])}
        moves = set()
        for mp in cand[p]:
            for s in _subsets(mp):
                got.add(T.flat_after(cp, s))
            for mv in mp:
                for s in _subsets([x for x in mp if x != mv]):
                    moves.add((T.move_index[mv], T.flat_after(cp, s)))
        poses[p] = sorted(got)
        starts[p] = moves
    kk, ss, mm, ii, jj = [], [], [], [], []
    lookup = T.lookup
    for p in todo:
        for k, q, side in T.adj[p]:
            js = poses.get(q) or [T.flat_after(c[q].tolist(), [])]
            for m, i in starts[p]:
                for j in js:
                    if lookup(k, side, m, i, j) is None:
                        kk.append(k)
                        ss.append(side)
                        mm.append(m)
                        ii.append(i)
                        jj.append(j)
    if kk:
        blocked_entries(T.problem, kk, ss, mm, ii, jj)


def descent(problem: Problem, c: np.ndarray, max_steps: int | None = None,
            check: Callable[..., None] | None = None) -> tuple[list[list[Move]], np.ndarray]:
    """Descent steps from ``c`` until all are at target or a stall: ``(steps, end)``.
    ``check(stage, **info)`` is called before every step (budgets, progress).  Every step
    brings a positioner one position closer to its target, so there are at most
    ``n · Σ joint positions`` of them (the bound when ``max_steps`` is None)."""
    T = _Lookups(problem)
    steps: list[list[Move]] = []
    c = c.copy()
    bound = problem.n * sum(j.steps for j in problem.kinematics.joints)
    limit = bound if max_steps is None else min(max_steps, bound)
    while len(steps) < limit:
        if check is not None:
            check("descent", iteration=len(steps))
        step = descent_step(problem, c, T)
        if not step:
            break
        for p, j, d in step:
            c[p] = T.pose(c[p], [(j, d)])
        steps.append(step)
    return steps, c
