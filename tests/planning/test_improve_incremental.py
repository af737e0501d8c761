"""Plan improvement made incremental gives the plan of the full recomputation; orders are kept per member set.

The reference re-planner below recomputes every mask of every step and option from the
tables on each call (the module's definition, one neighbour at a time) and makes every
attempt afresh; the incremental one keeps masks per positioner until a neighbour's
trajectory changes and skips attempts whose inputs did not change.
"""

from __future__ import annotations

import numpy as np
import pytest

import supcoord
from supcoord.planning.graph_order import _least_cutwidth, cutwidth_order, rcm_order
from supcoord.planning.guards import conflict_graph
from supcoord.planning.improve import _Replanner, _run_rounds
from supcoord.problems.plan import lower_bound
from supcoord.problems.presets import preset_problem


class _FullReplanner(_Replanner):
    """Every mask computed from the tables on every call; every attempt made afresh."""

    def layer_masks(self, r):
        steps = len(self.traj) - 1
        return np.array([[self._mask(r, t, u) for u in range(len(self.deltas))] for t in range(steps)],
                        dtype=bool).reshape(steps, len(self.deltas), len(self.pos))

    def _mask(self, r, t, u):
        ok = self.base(r)[u].copy()
        tables, n_single = self.tables, self.n_single
        for k, q, side in self.nbrs[r]:
            if q in self.absent:
                continue
            j0, j1 = int(self.traj[t, q]), int(self.traj[t + 1, q])
            at = {"at_b": j0} if side == 0 else {"at_a": j0}
            v = 0 if j0 == j1 else int(self.options_along(self.traj[t:t + 2, q])[0])
            conflict = (r, q) in self.conflict
            if u == 0 and v == 0:
                if conflict:
                    ok &= ~tables.static_line(k, **at)
            elif u == 0 and v < n_single:
                if conflict:
                    ok &= ~tables.swept_line(k, 1 - side, v - 1, **at)
            elif v == 0 and u < n_single:
                ok &= ~tables.swept_line(k, side, u - 1, **at)
            else:
                ok &= ~self.merged.hits(k, side, v, j0)[u]
        return ok

    def remembered_attempt(self, r, horizon, wide):
        return self.attempt(r, horizon, wide)


def _improved(cls, problem, confs, max_replans):
    stats = {"replans": 0, "improved": 0, "improved_with_blockers": 0, "improved_with_pairs": 0, "remembered": 0}
    rp = cls(problem, confs, stats)
    _run_rounds(rp, max_replans, lower_bound(problem))
    for wide in (False, True):  # once more, with nothing changed since the last: every attempt as before
        rp.round(max_replans + 40, wide=wide)
    return rp.traj, stats


CASES = [("sdss-v", 1, 0, 9, 5), ("sdss-v", 1, 1, 9, 5)]


@pytest.mark.timeout(300)  # about 3 s of CPU; the reference is slow by design
@pytest.mark.slow
def test_the_incremental_improvement_gives_the_plan_of_the_full_recomputation():
    remembered = improved = 0
    for name, rings, seed, a, b in CASES:
        p = preset_problem(name, rings=rings, seed=seed, alpha_steps=a, beta_steps=b)
        plan = supcoord.solve(p, improve=0, validation="none", simultaneous=None, finer=None)
        if plan.status != "complete":
            continue
        fast, st_fast = _improved(_Replanner, p, plan.configurations, 30)
        full, st_full = _improved(_FullReplanner, p, plan.configurations, 30)
        assert np.array_equal(fast, full), (name, seed)
        assert {k: v for k, v in st_fast.items() if k not in ("remembered", "rounds")} == \
               {k: v for k, v in st_full.items() if k not in ("remembered", "rounds")}
        remembered += st_fast["remembered"]
        improved += st_fast["improved"]
    assert remembered > 0 and improved > 0  # both the shortcuts and the improvements were exercised


def _strip():
    return preset_problem("sdss-v", rings=2, seed=0, alpha_steps=9, beta_steps=5)


def test_the_order_of_a_grown_window_is_its_own():
    p = _strip()
    adj = conflict_graph(p)
    window = [0, 1]
    first = cutwidth_order(p, window)
    grown = sorted(set(window) | {next(q for _, q, _ in adj[1] if q not in window)})
    order = cutwidth_order(p, grown)
    assert sorted(first) == window and sorted(order) == grown
    assert order == _least_cutwidth(p, tuple(grown), 10)
    assert cutwidth_order(p, list(reversed(grown))) == order  # the same member set: the same order


@pytest.mark.parametrize("members", [None, [0, 1, 2, 5, 6]])
def test_rcm_order_is_kept_per_member_set(members):
    p = _strip()
    once = rcm_order(p, members)
    assert rcm_order(p, members) == once
    assert sorted(once) == (list(range(p.n)) if members is None else sorted(members))
    assert sorted(rcm_order(p, [0, 1])) == [0, 1]
