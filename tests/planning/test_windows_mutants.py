"""The exact window over a whole small conflict component (``_Windows.whole``), watched
through the observer's ``whole_component`` hook and checked against the explicit oracle.

The local route solves a conflict component of few configurations by one exact search
before its descent; whatever that window returns, the later stages would still reach the
target, so only the window's own outcome shows a wrong verdict, a missing move list or a
certificate that does not name the component (mutants of ``whole`` that the route's final
plan hides)."""

import numpy as np
import pytest

from supcoord.errors import ModelError
from supcoord.planning.graph_order import conflict_components
from supcoord.planning.model import CoordinationModel
from supcoord.planning.windows import (
    SMALL_COMPONENT,
    Certificate,
    Local,
    WindowObserver,
    WindowOutcome,
    solve_local,
)
from supcoord.problems import random_problem
from supcoord.problems.plan import apply_moves
from supcoord.testing.oracle import oracle_solve

ROT = {"kind": "rotary", "arm": 15.0, "steps": 12}
# tight layouts (as tests/planning/test_planner.py): every robot conflicts with the others,
# so the whole problem is one conflict component of 12**n <= SMALL_COMPONENT configurations
LAYOUTS = {"rot2": [[0, 0], [20, 0]], "rot3": [[0, 0], [18, 0], [9, 15]]}
HOW = "exhaustive symbolic search of their conflict component"


class _Record(WindowObserver):
    def __init__(self):
        self.wholes: list[WindowOutcome] = []
        self.windows: list[WindowOutcome] = []

    def whole_component(self, outcome: WindowOutcome) -> None:
        self.wholes.append(outcome)

    def window(self, outcome: WindowOutcome) -> None:
        self.windows.append(outcome)


def _cases():
    return [(name, seed) for name in LAYOUTS for seed in range(5)]


@pytest.mark.parametrize("name,seed", _cases())
def test_whole_component_window_agrees_with_the_oracle(name, seed):
    p = random_problem(np.array(LAYOUTS[name], float), ROT, 2.0, seed=seed)
    everyone = list(range(p.n))
    assert conflict_components(p) == [everyone] and 12 ** p.n <= SMALL_COMPONENT
    distance = oracle_solve(p.to_json())  # the shortest single-move plan's length (None: no plan)
    rec = _Record()
    res = solve_local(p, CoordinationModel(p), Local(observer=rec))
    (out,) = rec.wholes  # one exact window, over the whole component, from the start
    if distance is None:
        assert out == WindowOutcome("infeasible", members=everyone, how=HOW)
        assert res.moves is None and res.certificate == Certificate(everyone, HOW)
        return
    assert out.kind == "solved" and out.members == everyone and out.how == "" and out.region == []
    assert len(out.moves) == distance  # a shortest plan
    assert np.array_equal(apply_moves(p, out.moves)[-1], p.target)
    assert res.certificate is None and res.moves == out.moves  # at target: nothing left to do


def test_the_cases_have_both_verdicts():
    verdicts = {oracle_solve(random_problem(np.array(LAYOUTS[n], float), ROT, 2.0, seed=s).to_json()) is None
                for n, s in _cases()}
    assert verdicts == {True, False}


def _contains(moves, part) -> bool:
    return any(moves[i:i + len(part)] == part for i in range(len(moves) - len(part) + 1))


@pytest.mark.parametrize("name,seed", _cases())
def test_grown_windows_are_what_the_route_applies(name, seed):
    """No component solved whole (``small_component=1``): the descent and the grown windows.
    Every window the observer sees is the one the route acted on: a solved window's moves are
    in the plan, and an infeasible one is the certificate."""
    p = random_problem(np.array(LAYOUTS[name], float), ROT, 2.0, seed=seed)
    distance = oracle_solve(p.to_json())
    rec = _Record()
    res = solve_local(p, CoordinationModel(p), Local(observer=rec, small_component=1))
    assert rec.wholes == [] and all(isinstance(o, WindowOutcome) for o in rec.windows)
    if distance is None:
        assert res.moves is None and rec.windows
        last = rec.windows[-1]
        assert last.kind == "infeasible" and res.certificate == Certificate(last.members, last.how)
        return
    assert np.array_equal(apply_moves(p, res.moves)[-1], p.target)
    for o in rec.windows:
        assert o.kind in ("solved", "gave_up")
        assert o.kind == "gave_up" or (o.moves and _contains(res.moves, o.moves))


def test_capped_last_level_is_refused_naming_the_levels():
    with pytest.raises(ModelError) as info:
        Local(levels=(1000, 5000)).check()
    assert info.value.value == (1000, 5000)
