"""The stopping rule of the plan improvement: a pair of rounds that leaves the makespan and
takes fewer than MIN_PROGRESS of the robots setting it out of them ends the rounds."""

from __future__ import annotations

import numpy as np

import supcoord
from supcoord.planning import improve
from supcoord.planning.improve import MIN_PROGRESS, _Replanner, _run_rounds, improve_plan
from supcoord.problems.presets import preset_problem
from supcoord.problems.plan import Plan
from supcoord.problems.validate import validate_plan


class _Scripted:
    """A re-planner whose rounds follow a script of (makespan, robots setting it) after each pair."""

    def __init__(self, script: list[tuple[int, int]], makespan: int, late: int):
        self.script = list(script)
        self.traj = np.zeros((makespan + 1, 1), dtype=np.int64)
        self._late = late
        self.stats = {"replans": 0}

    def late(self) -> int:
        return self._late

    def round(self, max_replans, check=None, wide=False):
        if wide:
            return False
        self.stats["replans"] += 10
        makespan, self._late = self.script.pop(0)
        self.traj = self.traj[:makespan + 1]
        return True


def test_a_pair_of_rounds_with_too_little_progress_ends_the_improvement():
    assert MIN_PROGRESS > 0.075
    rp = _Scripted([(9, 60), (9, 40), (9, 37), (8, 5), (7, 5)], makespan=9, late=100)
    _run_rounds(rp, 1000, floor=1)
    # 100 -> 60 -> 40 are progress; 40 -> 37 is not (7.5 %)
    assert rp.stats["stopped"] == "slow"
    assert [r[1] for r in rp.stats["rounds"]] == [9, 9, 9]
    assert [r[3] for r in rp.stats["rounds"]] == [60, 40, 37]


def test_a_shorter_plan_is_progress_however_many_robots_set_the_new_makespan():
    rp = _Scripted([(8, 500), (7, 900), (6, 2)], makespan=9, late=3)
    _run_rounds(rp, 1000, floor=6)
    assert rp.stats["stopped"] == "floor"
    assert len(rp.traj) - 1 == 6


def test_the_work_budget_still_bounds_the_rounds():
    rp = _Scripted([(9, 50), (9, 25), (9, 12)], makespan=9, late=100)
    _run_rounds(rp, 20, floor=1)
    assert rp.stats["stopped"] == "budget"
    assert rp.stats["replans"] == 20


def test_late_counts_the_robots_finishing_in_the_last_two_steps():
    p = preset_problem("desi", rings=2, seed=0, alpha_steps=13, beta_steps=7)
    plan = supcoord.solve(p, improve=0, validation="none")
    rp = _Replanner(p, [np.asarray(c) for c in plan.configurations], {"replans": 0})
    horizon = len(rp.traj) - 1
    assert rp.late() == sum(1 for r in range(p.n) if rp.finish(r) >= horizon - 1) > 0


def test_the_rule_stops_a_real_improvement_with_a_valid_plan(monkeypatch):
    p = preset_problem("desi", rings=5, seed=0, alpha_steps=13, beta_steps=7)
    plan = supcoord.solve(p, improve=0, validation="none")
    monkeypatch.setattr(improve, "MIN_PROGRESS", 1.0)  # every pair that keeps the makespan is too slow
    confs, stats = improve_plan(p, plan.configurations)
    makespans = [stats.makespan_before] + [r[1] for r in stats.rounds]
    shortened = [b < a for a, b in zip(makespans, makespans[1:])]
    assert all(shortened[:-1]) and (shortened[-1] or stats.stopped in ("slow", "no gain"))
    assert stats.makespan_after == len(confs) - 1 <= stats.makespan_before
    assert validate_plan(p, Plan("complete", confs, len(confs) - 1, plan.lower_bound, [], "", {})).valid
