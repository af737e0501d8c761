"""Shorter plans after the fact: re-plan the latest positioners in space-time.

Given a valid plan ``c_0 … c_T`` (every step collision-free as executed, the
validator's semantics), write ``τ_r(t)`` for positioner ``r``'s position at step ``t``
and ``f_r`` for the step after its last move (``T = max_r f_r``).  One *re-plan* of
``r`` keeps every other trajectory and searches ``r``'s earliest arrival in space-time::

    R(0) = {start_r},
    R(t+1) = {i + u : i ∈ R(t), u ∈ {stand} ∪ moves, step u allowed from i,
                      ∀ q neighbour of r.  r doing u from i while q does τ_q(t) → τ_q(t+1) is free}
    f'_r = least t with target_r ∈ R(t) such that r may stand at target during
           every step t … T' − 1  (T' = the plan's length)

(pairs checked as they move together: where one of the two stands, the exact swept tables
the planner already has; where both move, the certified motion
:func:`~supcoord.geometry.motion.motion_collides`, computed only for the neighbour's actual
moves, for every option and position of ``r`` at once, after the end-point bound of the
swept tables, in one batch per neighbour (:mod:`.merged_motion`): entry for entry the
pairs' whole simultaneous tables (:meth:`CollisionTables.simultaneous`), without computing them).
The new trajectory replaces the old when it arrives earlier; since every other
trajectory is unchanged and each of ``r``'s steps was checked against the others'
motion in that very step, the plan stays valid — and it still starts at the start and
ends at the target.  Rounds go over the positioners in order of decreasing ``f_r``
(the ones that set the makespan first) until a round improves nothing, a pair of rounds
neither shortens the plan nor takes a tenth of the positioners that set the makespan out of
them (:data:`MIN_PROGRESS`: past that point the gains measured did not pay for the work), the
plan is as short as the largest joint distance from start to target (no plan is shorter), or
the work budget (a number of re-plannings, never seconds: the same input gives the same plan
on any machine) runs out; trailing steps in which nothing moves are dropped.

A *group* re-plan takes the positioner ``r`` and some neighbours out (its latest ones;
failing those, the ones in the way of ``r``'s earliest arrival without neighbours), re-plans
them one after another (prioritised: each sees those already re-planned, not the
others), and keeps the result only if every one of them arrives and the group's last
arrival is earlier than before — otherwise the old trajectories are restored.  Each
accepted trajectory was checked, step by step, against every trajectory present in
the final plan, so the plan stays valid.

This changes the plan, never a verdict (the plan was already complete), so it may
use the simultaneous semantics, wider than the single-move model the verdicts are
about.  It is large-neighbourhood search with neighbourhoods of one to five
positioners around the ones that set the makespan.

References
----------
- D. Silver, Cooperative pathfinding, 2005 (space-time search around reserved paths).
- J. Li et al., Anytime multi-agent path finding via large neighborhood search, 2021.
"""

from __future__ import annotations

import itertools
import time
from collections import OrderedDict
from dataclasses import asdict, dataclass
from typing import Any, Callable

import numpy as np

from ..problems.plan import lower_bound
from ..problems.problem import Problem
from .guards import conflict_graph, pair_graph, successor_table
from .merged_motion import MergedMotions
from .pair_replan import pair_replan

__all__ = ["improve_plan", "ImproveStats", "default_replans", "REPLANS_PER_POSITIONER", "MIN_REPLANS", "MIN_PROGRESS"]

#: the default work budget of :func:`improve_plan` (space-time re-plannings tried)
REPLANS_PER_POSITIONER = 4
MIN_REPLANS = 200
#: the stopping rule of :func:`improve_plan`: a pair of rounds that leaves the makespan as it was
#: and takes fewer than this share of the robots setting it (finishing in its last two steps)
#: out of them ends the improvement.  Measured on APO's wok and DESI's preset at 5 to 41 rings
#: (benchmarks/results/nextgen_analysis.md): every makespan gained came after pairs that took
#: at least 10 % out; the pairs that took fewer (1.5–3 % of a thousand robots at 41 rings)
#: were followed by nothing gained, yet cost twice the work of all the gains before them
MIN_PROGRESS = 0.1
#: positioners whose masks (:meth:`_Replanner.layer_masks`, ``steps × options × positions``
#: Booleans: 120 kB for 20 steps on a 36 × 19 lattice) are kept, the latest used
LAYERS_KEPT = 256
#: bytes of per-neighbour masks (:meth:`_Replanner.free_against`) kept, the latest used: a
#: positioner's masks recomputed after one neighbour changed read the others' from here
AGAINST_BYTES_KEPT = 48 << 20


def _trajectories(problem: Problem, confs: list[np.ndarray]) -> np.ndarray:
    """``traj[t, r]`` = flat position of ``r`` at step ``t``."""
    kin = problem.kinematics
    return np.stack([kin.flat_index(c) for c in confs]).astype(np.int64)


def _step_options(problem: Problem) -> tuple[list[np.ndarray], int, np.ndarray]:
    """``(deltas, n_single, nxt)``: the options of one step — 0 stands, ``1 + m`` is
    ``moves()[m]`` (the move indices of the swept tables, plus one), then the moves of
    several joints at once (from ``n_single`` on) — and ``nxt[u, i]``, the flat position
    after option ``u`` from ``i`` (−1: past a hard stop)."""
    kin = problem.kinematics
    deltas = [np.zeros(kin.n_joints, dtype=np.int64)]
    for joint, d in kin.moves():
        e = np.zeros(kin.n_joints, dtype=np.int64)
        e[joint] = d
        deltas.append(e)
    n_single = len(deltas)
    for combo in itertools.product((0, 1, -1), repeat=kin.n_joints):
        if sum(1 for v in combo if v) >= 2:
            deltas.append(np.array(combo, dtype=np.int64))
    return deltas, n_single, successor_table(kin, deltas)


class _Replanner:
    """The trajectories of a plan being shortened and the re-plans of the module docstring."""

    def __init__(self, problem: Problem, confs: list[np.ndarray], stats: dict[str, Any]):
        self.problem = problem
        self.kin = kin = problem.kinematics
        self.pos = kin.all_positions()
        self.deltas, self.n_single, self.nxt = _step_options(problem)
        self.delta_of = {tuple(int(v) for v in d): u for u, d in enumerate(self.deltas)}
        self.nbrs = pair_graph(problem)
        self.conflict = {(p, q) for p in range(problem.n) for _, q, _ in conflict_graph(problem)[p]}
        self.tables = problem.tables()
        self.traj = _trajectories(problem, confs)
        self.stats = stats
        self.absent: set[int] = set()  # positioners being re-planned (not obstacles yet)
        self.merged_cache: dict[Any, Any] = {}  # merged motions by key; "pairs": pair_replan's latest tables
        self.merged = MergedMotions(problem, self.pos, self.deltas, self.n_single, self.nxt, self.merged_cache)
        self._options: dict[int, np.ndarray] = {}  # options(), per positioner
        #: a number per trajectory, new whenever one changes (from :attr:`_clock`): what a
        #: cached answer was computed from; an old trajectory restored gets its old number back
        self.version = np.zeros(problem.n, dtype=np.int64)
        self._clock = 0
        self._base: dict[int, np.ndarray] = {}  # r -> r's own constraints, [option, position]
        self._blocks: dict[tuple, np.ndarray] = {}  # (geometry, v, j0, conflict) -> block[option, position]
        #: r -> (what they were computed from, masks), the latest LAYERS_KEPT positioners used
        self._layers: OrderedDict[int, tuple[tuple, np.ndarray]] = OrderedDict()
        #: (r, q) -> (q's version and the plan's length, ~neighbour_blocks), the latest used
        self._against: OrderedDict[tuple[int, int], tuple[tuple[int, int], np.ndarray]] = OrderedDict()
        self._against_bytes = 0
        self._hood: dict[int, np.ndarray] = {}  # r -> r and its neighbours up to two away
        self._failed: dict[tuple[bool, int], tuple[tuple, int]] = {}  # (wide, r) -> (what it read, replans)

    def options_along(self, column: np.ndarray) -> np.ndarray:
        """The option index of each step of the trajectory ``column`` (flat positions)."""
        pos = self.pos
        deltas = self.kin.signed_delta(pos[column[:-1]], pos[column[1:]]).reshape(len(column) - 1, -1)
        return np.array([self.delta_of[tuple(d)] for d in deltas.tolist()], dtype=np.int64)

    def options(self, r: int) -> np.ndarray:
        """The option index of each of ``r``'s steps (computed per trajectory, until it changes)."""
        options = self._options.get(r)
        if options is None:
            options = self._options[r] = self.options_along(self.traj[:, r])
        return options

    def option_of(self, r: int, t: int) -> int:
        """The option index of ``r``'s step ``t``."""
        return int(self.options(r)[t])

    def prefetch(self, r: int, steps: int) -> None:
        """Compute the masks of ``r`` (:meth:`layer_masks`), whose merged motions are decided
        in one batch per neighbour; ``steps``: at most the plan's (kept for callers)."""
        if steps > 0:
            self.layer_masks(r)

    def set_trajectory(self, r: int, column: np.ndarray, version: int | None = None) -> None:
        """Give ``r`` the trajectory ``column``: a new :attr:`version` if it differs, or
        ``version`` (the one ``column`` had before: restoring an old trajectory)."""
        if not np.array_equal(self.traj[:, r], column):
            self._options.pop(r, None)
            if version is None:
                self._clock += 1
                version = self._clock
        self.traj[:, r] = column
        if version is not None:
            self.version[r] = version

    def finishes(self) -> np.ndarray:
        """:meth:`finish` of every positioner at once."""
        moved = self.traj[1:] != self.traj[:-1]
        if not len(moved):
            return np.zeros(self.problem.n, dtype=np.int64)
        return np.where(moved.any(axis=0), len(moved) - np.argmax(moved[::-1], axis=0), 0)

    def late(self) -> int:
        """How many positioners set the makespan: their last move in the plan's last two steps."""
        return int(np.count_nonzero(self.finishes() >= len(self.traj) - 2))

    def finish(self, r: int) -> int:
        """``f_r``: the step after ``r``'s last move (0: it never moves)."""
        moved = np.nonzero(self.traj[1:, r] != self.traj[:-1, r])[0]
        return int(moved[-1]) + 1 if len(moved) else 0

    def base(self, r: int) -> np.ndarray:
        """``base[u, i]``: ``r`` may do option ``u`` from ``i`` by its own constraints (hard
        stops, obstacles, held joints), whatever its neighbours do."""
        ok = self._base.get(r)
        if ok is None:
            ok = self.nxt >= 0
            unary = self.problem.unary().get(r)
            if unary is not None:
                ok[0] &= ~unary[0]
                for u in range(1, self.n_single):
                    ok[u] &= ~unary[1][u - 1]
                for u in range(self.n_single, len(self.deltas)):  # several joints at once
                    sel = np.nonzero(ok[u])[0]
                    ok[u, sel] = ~self.problem.own_motion_blocked(r, self.pos[sel], self.deltas[u])
            self._base[r] = ok
        return ok

    def block(self, k: int, side: int, conflict: bool, v: int, j0: int) -> np.ndarray:
        """``block[u, i]``: ``r`` (pair ``k``'s member on ``side``) doing option ``u`` from ``i`` hits
        its neighbour doing option ``v`` from ``j0`` during the same step (``conflict``: the pair
        is in the conflict graph; only then do the neighbour's swept and static tables count
        against a standing ``r``).  Cached per pair geometry: equal keys, equal tables."""
        key = self.merged.key(k, side, v, j0) + (conflict,)
        out = self._blocks.get(key)
        if out is not None:
            return out
        tables, n_single = self.tables, self.n_single
        out = np.zeros((len(self.deltas), len(self.pos)), dtype=bool)
        at = {"at_b": j0} if side == 0 else {"at_a": j0}
        if v == 0 and conflict:
            out[0] = tables.static_line(k, **at)
        elif v < n_single and conflict:  # q turns one joint past a standing r: q's swept table
            out[0] = tables.swept_line(k, 1 - side, v - 1, **at)
        for u in range(1, len(self.deltas)):
            if v == 0 and u < n_single:  # r turns one joint past a standing q: r's swept table
                out[u] = tables.swept_line(k, side, u - 1, **at)
            else:  # both move, or several joints at once: the merged motion
                out[u] = self.merged.hits(k, side, v, j0)[u]
        if v >= n_single:  # q moves several joints past a standing r
            out[0] = self.merged.hits(k, side, v, j0)[0]
        self._blocks[key] = out
        return out

    def neighbour_blocks(self, r: int, k: int, q: int, side: int) -> np.ndarray:
        """``out[t, u, i]``: ``r`` doing ``u`` from ``i`` during step ``t`` hits ``q`` doing its
        step ``t`` of the plan (:meth:`block` per distinct step of ``q``; the merged motions
        they need computed in one batch, :meth:`.MergedMotions.compute`)."""
        npos = len(self.pos)
        steps = len(self.traj) - 1  # the options may be those of a trajectory since cut short
        codes = (self.options(q)[:steps] * npos + self.traj[:-1, q]).tolist()
        uniq = sorted(set(codes))
        conflict = (r, q) in self.conflict
        wanted = [(c // npos, c % npos) for c in uniq]
        missing = [(v, j0) for v, j0 in wanted if (v > 0 or len(self.deltas) > self.n_single)
                   and self.merged.key(k, side, v, j0) + (conflict,) not in self._blocks
                   and not self.merged.known(k, side, v, j0)]
        if missing:
            self.merged.compute(k, side, missing)
        blocks = [self.block(k, side, conflict, v, j0) for v, j0 in wanted]
        if len(blocks) == 1:
            return np.broadcast_to(blocks[0], (steps,) + blocks[0].shape)
        index = {c: n for n, c in enumerate(uniq)}
        return np.stack(blocks)[[index[c] for c in codes]]

    def free_against(self, r: int, k: int, q: int, side: int) -> np.ndarray:
        """``~``:meth:`neighbour_blocks`: ``r`` may do ``u`` from ``i`` during step ``t`` as far as
        ``q`` doing its step ``t`` is concerned; kept per ``(r, q)`` until ``q``'s trajectory or
        the plan's length changes (the latest :data:`AGAINST_BYTES_KEPT` bytes)."""
        key = (int(self.version[q]), len(self.traj))
        cached = self._against.pop((r, q), None)
        if cached is not None and cached[0] != key:
            self._against_bytes -= cached[1].nbytes
            cached = None
        if cached is None:
            cached = (key, ~self.neighbour_blocks(r, k, q, side))
            self._against_bytes += cached[1].nbytes
        self._against[r, q] = cached
        while self._against_bytes > AGAINST_BYTES_KEPT and len(self._against) > 1:
            self._against_bytes -= self._against.popitem(last=False)[1][1].nbytes
        return cached[1]

    def layer_masks(self, r: int) -> np.ndarray:
        """``masks[t, u, i]``: ``r`` may do option ``u`` from ``i`` during step ``t`` against its own
        constraints and every present neighbour's step ``t``, for every step of the plan at once.

        Kept per positioner and recomputed only when the plan's length, the absent neighbours or
        a present neighbour's trajectory changed (:attr:`version`)."""
        present = [(k, q, side) for k, q, side in self.nbrs[r] if q not in self.absent]
        key = (len(self.traj), tuple((q, int(self.version[q])) for _, q, _ in present))
        cached = self._layers.pop(r, None)
        if cached is None or cached[0] != key:
            masks = np.repeat(self.base(r)[None], len(self.traj) - 1, axis=0)
            for k, q, side in present:
                masks &= self.free_against(r, k, q, side)
            cached = (key, masks)
        self._layers[r] = cached
        while len(self._layers) > LAYERS_KEPT:
            self._layers.popitem(last=False)
        return cached[1]

    def allowed_mask(self, r: int, t: int, u: int) -> np.ndarray:
        """Positions ``i`` of ``r`` from which option ``u`` during step ``t`` is free against all
        present neighbours (a row of :meth:`layer_masks`)."""
        return self.layer_masks(r)[t, u]

    def stay_from(self, r: int, goal: int, horizon: int) -> np.ndarray:
        """``stay_from[t]``: may ``r`` stand at ``goal`` during steps ``t … horizon − 1``?"""
        stay = np.append(self.layer_masks(r)[:horizon, 0, goal], True)
        return np.logical_and.accumulate(stay[::-1])[::-1]

    def replan(self, r: int, horizon: int, before: int) -> np.ndarray | None:
        """``r``'s earliest-arrival trajectory (length ``horizon + 1``) if it arrives before ``before``.

        Each step's successors come from every option at once; a position reached by several
        gets the parent of the first in (option, position) order."""
        npos = len(self.pos)
        goal = int(self.kin.flat_index(self.problem.target[r]))
        masks = self.layer_masks(r)
        stay_from = self.stay_from(r, goal, horizon)
        reach = np.zeros(npos, dtype=bool)
        reach[int(self.traj[0, r])] = True
        parents: list[np.ndarray] = []
        for t in range(min(before, horizon + 1)):
            if reach[goal] and stay_from[t]:
                break
            if t == horizon:
                return None
            us, idx = np.nonzero(masks[t] & reach)
            dst = self.nxt[us, idx]
            first = np.unique(dst, return_index=True)[1]
            par = np.full(npos, -1, dtype=np.int64)
            par[dst[first]] = idx[first]
            reach = np.zeros(npos, dtype=bool)
            reach[dst] = True
            parents.append(par)
            if not len(dst):
                return None
        else:
            return None
        arrival = len(parents)
        path = [goal]
        for par in reversed(parents):
            path.append(int(par[path[-1]]))
        path.reverse()
        out = self.traj[:, r].copy()
        out[:arrival + 1] = path
        out[arrival + 1:] = goal
        return out

    def regroup(self, group: list[int], horizon: int) -> bool:
        """Re-plan ``group`` one by one (prioritised, in this order, the rest of the group
        ignored until planned); keep it if the group's last arrival comes earlier."""
        old, versions = self.traj[:, group].copy(), self.version[group].copy()
        old_last = max(self.finish(g) for g in group)
        self.absent.update(group)
        ok = True
        for g in group:
            self.absent.discard(g)
            new = self.replan(g, horizon, old_last)
            self.stats["replans"] += 1
            if new is None:
                ok = False
                break
            self.set_trajectory(g, new)
        self.absent.clear()
        if not ok:
            for g, column, version in zip(group, old.T, versions.tolist()):
                self.set_trajectory(g, column, version)
        return ok

    def _first_group(self, groups: list[list[int]], horizon: int) -> bool:
        """Re-plan the first of ``groups`` that :meth:`regroup` can shorten; did one?"""
        return any(len(set(g)) == len(g) and self.regroup(g, horizon) for g in groups)

    def blockers(self, r: int, horizon: int) -> list[int]:
        """The neighbours in the way of ``r``'s earliest arrival without them (its own
        constraints only), in the order they first block that path."""
        near = [q for _, q, _ in self.nbrs[r]]
        self.absent = set(near)
        path = self.replan(r, horizon, horizon + 1)
        self.stats["replans"] += 1
        first: dict[int, int] = {}
        if path is not None:
            u, i = self.options_along(path[:horizon + 1]), path[:horizon]
            own = ~self.base(r)[u, i]
            for k, q, side in self.nbrs[r]:
                hit = own | self.neighbour_blocks(r, k, q, side)[np.arange(horizon), u, i]
                if hit.any():
                    first[q] = int(np.argmax(hit))
        self.absent = set()
        return sorted(first, key=lambda q: (first[q], q))

    def replan_pair(self, r: int, q: int, horizon: int) -> bool:
        """Re-plan neighbours ``r`` and ``q`` together (:mod:`.pair_replan`); keep the result if
        their last arrival comes earlier."""
        k, side = next((k, side) for k, x, side in self.nbrs[r] if x == q)
        new = pair_replan(self, r, q, k, side, horizon, max(self.finish(r), self.finish(q)))
        self.stats["replans"] += 1
        if new is None:
            return False
        self.set_trajectory(r, new[0])
        self.set_trajectory(q, new[1])
        return True

    def attempt(self, r: int, horizon: int, wide: bool) -> bool:
        """Shorten ``r``'s part of the plan: groups of one to three with its latest neighbours
        (``wide``: groups of up to five with the neighbours in its way, then a neighbour in its
        way re-planned with it together).  Did it?"""
        finish = self.finish
        late = sorted((q for _, q, _ in self.nbrs[r] if finish(q) > 0), key=lambda q: (-finish(q), q))
        groups = [[r], [r] + late[:1], [r] + late[:2], late[:2] + [r]]
        if not wide:
            return self._first_group(groups, horizon)
        blockers = self.blockers(r, horizon)
        if self._first_group(_blocker_groups(r, blockers, groups), horizon):
            self.stats["improved_with_blockers"] += 1
        elif any(self.replan_pair(r, q, horizon) for q in blockers[:2]):
            self.stats["improved_with_pairs"] += 1
        else:
            return False
        return True

    def remembered_attempt(self, r: int, horizon: int, wide: bool) -> bool:
        """:meth:`attempt`, unless the same attempt failed before with every trajectory it reads
        unchanged (``r`` and the positioners up to two neighbours away, :attr:`version`) and the
        same plan length: then it fails again, and its re-plannings are counted again, so that
        the work budget and the plan are those of the attempt made afresh."""
        hood = self._hood.get(r)
        if hood is None:
            near = {q for _, q, _ in self.nbrs[r]}
            hood = self._hood[r] = np.array(sorted(near.union(*({x for _, x, _ in self.nbrs[q]} for q in near),
                                                               {r})), dtype=np.int64)
        key = (horizon, self.version[hood].tobytes())
        failed = self._failed.get((wide, r))
        if failed is not None and failed[0] == key:
            self.stats["replans"] += failed[1]
            self.stats["remembered"] += 1
            return False
        before = self.stats["replans"]
        if self.attempt(r, horizon, wide):
            return True
        self._failed[wide, r] = (key, self.stats["replans"] - before)
        return False

    def round(self, max_replans: int, check: Callable[[], None] | None = None, wide: bool = False) -> bool:
        """One round over the positioners that set the makespan, latest first
        (:meth:`remembered_attempt`); trailing idle steps dropped.  Did it improve anything?"""
        improved = False
        horizon = len(self.traj) - 1
        finish = self.finish
        for r in np.lexsort((np.arange(self.problem.n), -self.finishes())).tolist():  # latest first
            if self.stats["replans"] >= max_replans or finish(r) == 0:
                break
            if check is not None:
                check()
            if finish(r) < horizon - 1:
                break  # only the positioners that set the makespan
            if self.remembered_attempt(r, horizon, wide):
                self.stats["improved"] += 1
                improved = True
        self.traj = self.traj[:int(self.finishes().max(initial=0)) + 1]
        return improved


def _blocker_groups(r: int, blockers: list[int], tried: list[list[int]]) -> list[list[int]]:
    """Groups of ``r`` with the neighbours in its way (:meth:`_Replanner.blockers`), ``r``
    first or last, that are not among ``tried``."""
    b = blockers  # short for the table of groups below
    out: list[list[int]] = []
    for g in ([r] + b[:1], [r] + b[:2], [r] + b[:3], [r] + b[:4], b[:2] + [r], b[:3] + [r]):
        if len(g) > 1 and g not in tried and g not in out:
            out.append(g)
    return out


@dataclass(frozen=True)
class ImproveStats:
    """What :func:`improve_plan` did: the makespan ``makespan_before`` and ``makespan_after``
    (steps), the space-time re-plannings tried (``replans``, at most ``max_replans``), the
    groups that shortened the plan (``improved``; of them ``improved_with_blockers`` with the
    robots in the way, ``improved_with_pairs`` by a pair re-planned together) and the time
    taken (``seconds``, wall clock); ``remembered``: attempts not redone because nothing near
    the robot changed since they failed; ``rounds``: after each pair of rounds, ``(re-plannings
    so far, makespan, CPU seconds, robots setting the makespan)``; ``stopped``: why the rounds
    ended — ``"floor"`` (no plan is shorter), ``"budget"`` (``max_replans`` tried), ``"no gain"``
    (a round improved nothing) or ``"slow"`` (:data:`MIN_PROGRESS`)."""

    makespan_before: int
    replans: int
    improved: int
    improved_with_blockers: int
    improved_with_pairs: int
    max_replans: int
    makespan_after: int
    seconds: float
    remembered: int = 0
    rounds: tuple[tuple[int, int, float, int], ...] = ()
    stopped: str = ""

    def to_json(self) -> dict[str, Any]:
        """The statistics as a JSON object, in the order of the fields."""
        return asdict(self)



def improve_plan(problem: Problem, confs: list[np.ndarray], max_replans: int | None = None,
                 check: Callable[[], None] | None = None) -> tuple[list[np.ndarray], ImproveStats]:
    """A plan no longer than ``confs`` (module docstring) and statistics.

    Rounds go on until one improves nothing, a pair of rounds makes too little progress
    (:data:`MIN_PROGRESS`) or ``max_replans`` space-time re-plannings have been tried
    (default :func:`default_replans`): budget and rule count work, not seconds, so the same
    problem gives the same plan on any machine and any load.  ``check`` (the
    caller's budget check) is called before each group and may raise."""
    t0 = time.perf_counter()
    if max_replans is None:
        max_replans = default_replans(problem.n)
    kin = problem.kinematics
    stats: dict[str, Any] = {"makespan_before": len(confs) - 1, "replans": 0, "improved": 0, "improved_with_blockers": 0,
                             "improved_with_pairs": 0, "remembered": 0,
                             "max_replans": int(max_replans)}
    rp = _Replanner(problem, confs, stats)
    _run_rounds(rp, max_replans, lower_bound(problem), check)
    stats["makespan_after"] = len(rp.traj) - 1
    stats["seconds"] = time.perf_counter() - t0
    out = [rp.pos[row] for row in rp.traj]
    return [np.asarray(c, dtype=np.int64).reshape(problem.n, kin.n_joints) for c in out], ImproveStats(**dict(stats, rounds=tuple(stats.get("rounds", ()))))


def _run_rounds(rp: _Replanner, max_replans: int, floor: int, check: Callable[[], None] | None = None) -> None:
    """Rounds of ``rp`` until one improves nothing, a pair of them leaves the makespan and takes
    fewer than :data:`MIN_PROGRESS` of the robots setting it out of them, ``max_replans``
    re-plannings were tried or the plan is ``floor`` steps long; ``rp.stats["rounds"]`` gets
    ``(re-plannings so far, makespan, CPU seconds, robots setting the makespan)`` after each
    pair of rounds, ``rp.stats["stopped"]`` the reason (:class:`ImproveStats`)."""
    t0 = time.process_time()
    rounds = rp.stats.setdefault("rounds", [])
    late = rp.late()
    while True:
        if len(rp.traj) - 1 <= floor or rp.stats["replans"] >= max_replans:
            rp.stats["stopped"] = "floor" if len(rp.traj) - 1 <= floor else "budget"
            return
        makespan = len(rp.traj) - 1
        # the wide groups only where the narrow ones are stuck
        improved = rp.round(max_replans, check) or rp.round(max_replans, check, wide=True)
        late, before = rp.late(), late
        rounds.append((rp.stats["replans"], len(rp.traj) - 1, round(time.process_time() - t0, 3), late))
        if not improved:
            rp.stats["stopped"] = "no gain"
            return
        if len(rp.traj) - 1 == makespan and before - late < MIN_PROGRESS * before:
            rp.stats["stopped"] = "slow"
            return


def default_replans(positioners: int) -> int:
    """The default work budget of :func:`improve_plan`: :data:`REPLANS_PER_POSITIONER` re-plannings
    per positioner, at least :data:`MIN_REPLANS`."""
    return max(MIN_REPLANS, REPLANS_PER_POSITIONER * int(positioners))
