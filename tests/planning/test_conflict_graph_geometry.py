"""The conflict graph's pairs are decided once per pair geometry and are those of the per-pair definition."""

from __future__ import annotations

from supcoord.planning import guards
from supcoord.planning.guards import _blocking_pairs, _move_blocked_any
from supcoord.problems import parse_problem
from supcoord.problems.presets import preset_problem
from supcoord.testing.oracle.tight_problems import tight_problem


def _per_pair(problem):
    kin = problem.kinematics
    pos = kin.all_positions()
    valid = [kin.step_valid(pos, joint, delta) for joint, delta in kin.moves()]
    return [k for k in range(len(problem.pairs)) if _move_blocked_any(problem, k, valid)]


def test_blocking_pairs_are_those_of_the_definition_when_some_pair_never_blocks():
    problem = parse_problem(tight_problem(27))  # 8 pairs, one of which never blocks a move
    want = _per_pair(problem)
    assert 0 < len(want) < len(problem.pairs)
    assert _blocking_pairs(problem) == want


def test_blocking_pairs_are_decided_once_per_geometry(monkeypatch):
    problem = preset_problem("desi", rings=3, alpha_steps=7, beta_steps=5)
    want = _per_pair(problem)
    calls = []
    real = guards._move_blocked_any
    monkeypatch.setattr(guards, "_move_blocked_any", lambda p, k, valid: calls.append(k) or real(p, k, valid))
    assert _blocking_pairs(problem) == want
    assert len(calls) == len({problem.pair_geometry_key(k) for k in range(len(problem.pairs))}) < len(problem.pairs)
