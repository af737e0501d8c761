"""The improvement's per-neighbour masks: kept within their byte bound, the same plan whatever the bound."""

from __future__ import annotations

import numpy as np

import supcoord
from supcoord.planning import improve
from supcoord.planning.improve import _Replanner, _run_rounds
from supcoord.problems.plan import lower_bound
from supcoord.problems.presets import preset_problem


def _run(problem, confs):
    stats = {"replans": 0, "improved": 0, "improved_with_blockers": 0, "improved_with_pairs": 0, "remembered": 0}
    rp = _Replanner(problem, confs, stats)
    _run_rounds(rp, 40, lower_bound(problem))
    return rp, stats


def test_the_neighbour_masks_stay_within_their_bound_and_change_no_plan(monkeypatch):
    p = preset_problem("sdss-v", rings=1, seed=1, alpha_steps=9, beta_steps=5)
    plan = supcoord.solve(p, improve=0, validation="none", simultaneous=None, finer=None)
    assert plan.status == "complete"
    free, st_free = _run(p, plan.configurations)
    assert st_free["replans"] > 0 and len(free._against) > 1
    one = next(iter(free._against.values()))[1].nbytes
    monkeypatch.setattr(improve, "AGAINST_BYTES_KEPT", 3 * one)
    tight, st_tight = _run(p, plan.configurations)
    assert 1 <= len(tight._against) <= 3  # the oldest dropped
    assert tight._against_bytes == sum(m.nbytes for _, m in tight._against.values()) <= 3 * one
    assert np.array_equal(tight.traj, free.traj)
    assert {k: v for k, v in st_tight.items() if k != "rounds"} == {k: v for k, v in st_free.items() if k != "rounds"}
