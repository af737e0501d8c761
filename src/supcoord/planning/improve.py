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
(the ones that set the makespan first) until a round improves nothing, the plan is as
short as the largest joint distance from start to target (no plan is shorter), or the
work budget (a number of re-plannings, never seconds: the same input gives the same plan
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
from dataclasses import asdict, dataclass
from typing import Any, Callable

import numpy as np

from ..problems.plan import lower_bound
from ..problems.problem import Problem
from .guards import conflict_graph, pair_graph, successor_table
from .merged_motion import MergedMotions
from .pair_replan import pair_replan

__all__ = ["improve_plan", "ImproveStats", "default_replans", "REPLANS_PER_POSITIONER", "MIN_REPLANS"]

#: the default work budget of :func:`improve_plan` (space-time re-plannings tried)
REPLANS_PER_POSITIONER = 4
MIN_REPLANS = 200


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
        self.merged_cache: dict[tuple, np.ndarray] = {}
        self.merged = MergedMotions(problem, self.pos, self.deltas, self.n_single, self.nxt, self.merged_cache)
        self._options: dict[int, list[int]] = {}  # option_of, per positioner

    def option_of(self, r: int, t: int) -> int:
        """The option index of ``r``'s step ``t`` (computed per trajectory, until it changes)."""
        options = self._options.get(r)
        if options is None:
            pos, column = self.pos, self.traj[:, r]
            deltas = self.kin.signed_delta(pos[column[:-1]], pos[column[1:]]).reshape(len(column) - 1, -1)
            options = self._options[r] = [self.delta_of[tuple(int(v) for v in d)] for d in deltas.tolist()]
        return options[t]

    def set_trajectory(self, r: int, column: np.ndarray) -> None:
        self.traj[:, r] = column
        self._options.pop(r, None)

    def finish(self, r: int) -> int:
        """``f_r``: the step after ``r``'s last move (0: it never moves)."""
        moved = np.nonzero(self.traj[1:, r] != self.traj[:-1, r])[0]
        return int(moved[-1]) + 1 if len(moved) else 0

    def allowed_mask(self, r: int, t: int, u: int) -> np.ndarray:
        """Positions ``i`` of ``r`` from which option ``u`` during step ``t`` is free against all neighbours."""
        ok = self.nxt[u] >= 0
        unary = self.problem.unary().get(r)
        if unary is not None and u < self.n_single:  # r's own constraints (obstacles, held)
            ok = ok & ~(unary[0] if u == 0 else unary[1][u - 1])
        elif unary is not None:  # several joints at once
            key = ("own", r, u)
            if key not in self.merged_cache:
                own = np.ones(len(self.pos), dtype=bool)
                sel = np.nonzero(ok)[0]
                own[sel] = self.problem.own_motion_blocked(r, self.pos[sel], self.deltas[u])
                self.merged_cache[key] = own
            ok = ok & ~self.merged_cache[key]
        for k, q, side in self.nbrs[r]:
            if q in self.absent:
                continue
            j0, j1 = int(self.traj[t, q]), int(self.traj[t + 1, q])
            v = 0 if j0 == j1 else self.option_of(q, t)
            if u == 0 and v == 0:
                if (r, q) in self.conflict:
                    ok &= ~(self.tables.static_line(k, at_b=j0) if side == 0 else self.tables.static_line(k, at_a=j0))
            elif u == 0 and v < self.n_single:  # q turns one joint past a standing r: q's swept table
                if (r, q) in self.conflict:
                    # swept(k, 1 − side)[move of q, at_a, at_b], q at j0
                    ok &= ~(self.tables.swept_line(k, 1 - side, v - 1, at_b=j0) if side == 0 else
                            self.tables.swept_line(k, 1 - side, v - 1, at_a=j0))
            elif v == 0 and u < self.n_single:  # r turns one joint past a standing q: r's swept table
                ok &= ~(self.tables.swept_line(k, side, u - 1, at_b=j0) if side == 0 else
                        self.tables.swept_line(k, side, u - 1, at_a=j0))
            else:  # both move, or several joints at once: the merged motion, for every position of r at once
                ok &= ~self.merged.hits(k, side, v, j0)[u]
        return ok

    def prefetch(self, r: int, steps: int) -> None:
        """Compute, one batch per neighbour, the merged motions (:meth:`.MergedMotions.hits`)
        that :meth:`allowed_mask` will read for ``r`` during steps ``0 … steps − 1`` (each
        moving step of a present neighbour): the certified motions are many small numpy operations, so one call per
        pair instead of one per step (the same Booleans: every entry is decided on its own).
        ``benchmarks/vs_kaiju.py`` on the APO wok: 15–35 s CPU an instance against 17–41 s
        before, with the same plans."""
        for k, q, side in self.nbrs[r]:
            if q in self.absent:
                continue
            column = self.traj[:steps + 1, q]
            wanted = []
            for t in np.nonzero(column[1:] != column[:-1])[0].tolist():
                v, j0 = self.option_of(q, t), int(column[t])
                if not self.merged.known(k, side, v, j0) and (v, j0) not in wanted:
                    wanted.append((v, j0))
            if wanted:
                self.merged.compute(k, side, wanted)

    def stay_from(self, r: int, goal: int, horizon: int) -> list[bool]:
        """``stay_from[t]``: may ``r`` stand at ``goal`` during steps ``t … horizon − 1``?"""
        stay = [bool(self.allowed_mask(r, t, 0)[goal]) for t in range(horizon)]
        stay_from = [True] * (horizon + 1)
        for t in range(horizon - 1, -1, -1):
            stay_from[t] = stay_from[t + 1] and stay[t]
        return stay_from

    def replan(self, r: int, horizon: int, before: int) -> np.ndarray | None:
        """``r``'s earliest-arrival trajectory (length ``horizon + 1``) if it arrives before ``before``."""
        npos = len(self.pos)
        goal = int(self.kin.flat_index(self.problem.target[r]))
        self.prefetch(r, horizon)
        stay_from = self.stay_from(r, goal, horizon)
        reach = np.zeros(npos, dtype=bool)
        reach[int(self.traj[0, r])] = True
        parents: list[np.ndarray] = []
        for t in range(min(before, horizon + 1)):
            if reach[goal] and stay_from[t]:
                break
            if t == horizon:
                return None
            par = np.full(npos, -1, dtype=np.int64)
            new = np.zeros(npos, dtype=bool)
            for u in range(len(self.deltas)):
                idx = np.nonzero(reach & self.allowed_mask(r, t, u))[0]
                dst = self.nxt[u, idx]
                fresh = ~new[dst]
                par[dst[fresh]] = idx[fresh]
                new[dst] = True
            parents.append(par)
            reach = new
            if not reach.any():
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
        old = self.traj[:, group].copy()
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
            for g, column in zip(group, old.T):
                self.set_trajectory(g, column)
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
        for t in range(horizon if path is not None else 0):
            i, j = int(path[t]), int(path[t + 1])
            u = 0 if i == j else self.delta_of[tuple(int(v) for v in self.kin.signed_delta(self.pos[i], self.pos[j]))]
            for q in near:
                if q not in first:
                    self.absent = set(near) - {q}
                    if not self.allowed_mask(r, t, u)[i]:
                        first[q] = t
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

    def round(self, max_replans: int, check: Callable[[], None] | None = None, wide: bool = False) -> bool:
        """One round over the positioners that set the makespan, latest first (groups of
        one to three with their latest neighbours; ``wide``: groups of up to five with the
        neighbours in its way, then a neighbour in its way re-planned with it together);
        trailing idle steps dropped.  Did it improve anything?"""
        improved = False
        horizon = len(self.traj) - 1
        finish = self.finish
        for r in sorted(range(self.problem.n), key=lambda r: (-finish(r), r)):
            if self.stats["replans"] >= max_replans or finish(r) == 0:
                break
            if check is not None:
                check()
            if finish(r) < horizon - 1:
                break  # only the positioners that set the makespan
            late = sorted((q for _, q, _ in self.nbrs[r] if finish(q) > 0), key=lambda q: (-finish(q), q))
            groups = [[r], [r] + late[:1], [r] + late[:2], late[:2] + [r]]
            if not wide:
                if self._first_group(groups, horizon):
                    self.stats["improved"] += 1
                    improved = True
                continue
            blockers = self.blockers(r, horizon)
            if self._first_group(_blocker_groups(r, blockers, groups), horizon):
                self.stats["improved_with_blockers"] += 1
            elif any(self.replan_pair(r, q, horizon) for q in blockers[:2]):
                self.stats["improved_with_pairs"] += 1
            else:
                continue
            self.stats["improved"] += 1
            improved = True
        last = max(finish(r) for r in range(self.problem.n))
        self.traj = self.traj[:last + 1]
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
    taken (``seconds``, wall clock)."""

    makespan_before: int
    replans: int
    improved: int
    improved_with_blockers: int
    improved_with_pairs: int
    max_replans: int
    makespan_after: int
    seconds: float

    def to_json(self) -> dict[str, Any]:
        """The statistics as a JSON object, in the order of the fields."""
        return asdict(self)

    def __getitem__(self, key: str) -> Any:
        """The field ``key``: ``stats["replans"]``, the call form of the dictionary
        :func:`improve_plan` returned before this class."""
        return self.to_json()[key]


def improve_plan(problem: Problem, confs: list[np.ndarray], max_replans: int | None = None,
                 check: Callable[[], None] | None = None) -> tuple[list[np.ndarray], ImproveStats]:
    """A plan no longer than ``confs`` (module docstring) and statistics.

    Rounds go on until one improves nothing or ``max_replans`` space-time re-plannings have
    been tried (default :func:`default_replans`): a budget in units of work, not seconds,
    so the same problem gives the same plan on any machine and any load.  ``check`` (the
    caller's budget check) is called before each group and may raise."""
    t0 = time.perf_counter()
    if max_replans is None:
        max_replans = default_replans(problem.n)
    kin = problem.kinematics
    stats: dict[str, Any] = {"makespan_before": len(confs) - 1, "replans": 0, "improved": 0, "improved_with_blockers": 0,
                             "improved_with_pairs": 0,
                             "max_replans": int(max_replans)}
    rp = _Replanner(problem, confs, stats)
    improved = True
    floor = lower_bound(problem)  # no plan is shorter: nothing left to gain
    while improved and stats["replans"] < max_replans and len(rp.traj) - 1 > floor:
        # the wide groups only where the narrow ones are stuck
        improved = rp.round(max_replans, check) or rp.round(max_replans, check, wide=True)
    stats["makespan_after"] = len(rp.traj) - 1
    stats["seconds"] = time.perf_counter() - t0
    out = [rp.pos[row] for row in rp.traj]
    return [np.asarray(c, dtype=np.int64).reshape(problem.n, kin.n_joints) for c in out], ImproveStats(**stats)


def default_replans(positioners: int) -> int:
    """The default work budget of :func:`improve_plan`: :data:`REPLANS_PER_POSITIONER` re-plannings
    per positioner, at least :data:`MIN_REPLANS`."""
    return max(MIN_REPLANS, REPLANS_PER_POSITIONER * int(positioners))
