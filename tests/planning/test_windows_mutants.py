"""The exact window over a whole small conflict component (``_Windows.whole``), watched
through the observer's ``whole_component`` hook and checked against the explicit oracle.

The local route solves a conflict component of few configurations by one exact search
before its descent; whatever that window returns, the later stages would still reach the
target, so only the window's own outcome shows a wrong verdict, a missing move list or a
certificate that does not name the component (mutants of ``whole`` that the route's final
plan hides)."""

import dataclasses

import numpy as np
import pytest

from supcoord.errors import InputError, ModelError
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


# the window route forced (as tests/helpers/routes.py's "windows B"): small node caps, no descent,
# every conflict component left to the grown windows; on this 7-robot hexagon one window is
# solved by the few-displaced shortcut and the first level's caps are hit
FORCED = Local(levels=(12, 40, 135, None), descent="none", small_component=0)
HEX = {"kind": "hex", "rings": 1, "pitch": 20.0}


class _Windows(WindowObserver):
    def __init__(self):
        self.windows: list[WindowOutcome] = []
        self.few: list[int] = []  # indices in ``windows`` of those the shortcut solved
        self.few_moves: list = []  # the moves the shortcut reported for each

    def few_displaced_solved(self, moves) -> None:
        self.few.append(len(self.windows))
        self.few_moves.append(moves)

    def window(self, outcome: WindowOutcome) -> None:
        self.windows.append(outcome)


def test_few_displaced_plans_keep_all_but_two_members_in_place():
    """The shortcut's plan moves only window members and, besides one of them (the stuck
    robot), never has more than two members away from where the window found them
    (``DISPLACED``), read off the configurations the plan visits, not the restriction."""
    p = random_problem(HEX, ROT, 2.0, seed=1)
    rec = _Windows()
    res = solve_local(p, CoordinationModel(p), dataclasses.replace(FORCED, observer=rec))
    solved = [o for o in rec.windows if o.kind == "solved"]
    assert rec.few and res.moves == [m for o in solved for m in o.moves]  # no descent: the windows' moves only
    confs = apply_moves(p, res.moves)
    assert np.array_equal(confs[-1], p.target)
    at = 0
    for i, o in enumerate(rec.windows):
        if o.kind != "solved":
            continue
        seen = confs[at:at + len(o.moves) + 1]
        at += len(o.moves)
        if i not in rec.few:
            continue
        assert rec.few_moves[rec.few.index(i)] == o.moves  # the shortcut's own plan is the window's
        away = [{q for q in range(p.n) if not np.array_equal(x[q], seen[0][q])} for x in seen]
        assert set().union(*away) <= set(o.members)
        assert any(all(len(a - {r}) <= 2 for a in away) for r in o.members)
        assert len(o.members) >= 3  # the shortcut only runs with at least two other members


def test_capped_windows_give_up_and_the_uncapped_level_concludes():
    """Windows capped at 12 BDD nodes give up (their region: the window and its neighbours);
    the caps change only the work, so the plan is still complete."""
    p = random_problem(HEX, ROT, 2.0, seed=1)
    rec = _Windows()
    res = solve_local(p, CoordinationModel(p), dataclasses.replace(FORCED, observer=rec))
    gave_up = [o for o in rec.windows if o.kind == "gave_up"]
    assert gave_up and np.array_equal(apply_moves(p, res.moves)[-1], p.target)
    neighbours = {r: {r} for r in range(p.n)}
    for a, b in np.asarray(p.pairs).tolist():
        neighbours[a].add(b)
        neighbours[b].add(a)
    for o in gave_up:  # S ∪ N(S) for some window S: contains the neighbours of one of its robots
        assert any(neighbours[r] <= set(o.region) for r in o.region)


def test_every_descent_step_is_offered_to_the_budget():
    """Each step of the greedy descent is reported to the model's progress hook (where a budget
    stops a run), the last stalled one too: at least one report more than the steps taken."""
    p = random_problem(HEX, ROT, 2.0, seed=1)
    stages = []
    model = CoordinationModel(p, progress=lambda stage, info: stages.append(stage))
    res = solve_local(p, model, Local(small_component=0))
    assert res.stats.descent_steps > 0
    assert stages.count("descent") >= res.stats.descent_steps + 1


@pytest.mark.parametrize("field,bad,message", [
    ("descent", "steepest", "unknown descent 'steepest' (use greedy or none)"),
    ("direction", "sideways", "unknown direction 'sideways' (use easier, forward, reverse)")])
def test_unknown_options_are_refused_naming_field_and_value(field, bad, message):
    with pytest.raises(InputError) as info:
        dataclasses.replace(Local(), **{field: bad}).check()
    assert str(info.value) == f"{field}: {message}"
    assert (info.value.value, info.value.where) == (bad, field)


def test_window_counters_are_what_the_observer_and_the_model_see(monkeypatch):
    """The few-displaced solves counted are those the observer saw; the relaxed checks are the
    relaxed systems (no outsider frozen) built for windows of two members or more; the windows'
    own managers held nodes."""
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 19.0}, ROT, 2.0, seed=5)
    relaxed = []
    system = CoordinationModel.system

    def spy(self, members, frozen, **kw):
        if frozen is None and len(members) > 1:
            relaxed.append(list(members))
        return system(self, members, frozen, **kw)

    monkeypatch.setattr(CoordinationModel, "system", spy)
    rec = _Windows()
    res = solve_local(p, CoordinationModel(p), dataclasses.replace(FORCED, observer=rec))
    assert len(rec.few) >= 2 and res.stats.windows_few_displaced == len(rec.few)
    # every window that reached its goal is counted under its number of members
    solved = [str(len(o.members)) for o in rec.windows if o.kind == "solved"]
    assert res.stats.window_sizes == {n: solved.count(n) for n in set(solved)}
    assert relaxed and res.stats.relaxed_checks == len(relaxed)
    assert res.stats.window_peak_nodes > 0


def test_singleton_windows_leave_the_windows_peak_at_zero():
    """Windows of one robot run on the shared model, whose nodes are not the windows' own."""
    p = random_problem(np.array(LAYOUTS["rot3"], float), ROT, 2.0, seed=2)
    rec = _Record()
    res = solve_local(p, CoordinationModel(p), Local(observer=rec, small_component=1))
    assert rec.windows and all(o.members == [o.members[0]] for o in rec.windows if o.kind == "solved")
    assert res.stats.largest_window == 1 and res.stats.window_peak_nodes == 0


def test_the_descended_hook_sees_every_step():
    p = random_problem(HEX, ROT, 2.0, seed=1)
    seen = []

    class Steps(WindowObserver):
        def descended(self, steps):
            seen.append(steps)

    res = solve_local(p, CoordinationModel(p), Local(small_component=0, observer=Steps()))
    assert seen and sum(len(s) for s in seen) == res.stats.descent_steps > 0
    assert sum(len(step) for s in seen for step in s) == res.stats.descent_moves


@pytest.mark.parametrize("name,seed", [(n, s) for n, s in _cases()])
def test_an_infeasible_grown_window_says_how(name, seed):
    p = random_problem(np.array(LAYOUTS[name], float), ROT, 2.0, seed=seed)
    rec = _Record()
    res = solve_local(p, CoordinationModel(p), Local(observer=rec, small_component=1))
    if res.certificate is None:
        return
    last = rec.windows[-1]
    assert last.members and set(last.members) <= set(range(p.n))  # the robots the certificate is about
    assert last.how in (HOW, "exhaustive symbolic search of this relaxed subproblem",
                        "their reachable configurations were computed exactly and no other positioner restricts them")
    assert res.certificate.how == last.how
