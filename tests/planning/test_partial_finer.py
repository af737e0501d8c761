"""Step 4 of the partial search (issue 37): robots left off target by certificates of the
problem's lattice are put back where the finer lattice has a plan with them on target."""

import numpy as np

from supcoord.errors import BudgetExceeded
from supcoord.planning.partial import partial_search
from supcoord.problems.plan import Plan
from supcoord.problems.problem import parse_problem

TRIANGLE = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [18.0, 0.0], [9.0, 15.0]]},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
            "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]}


def _off(problem, sub):
    return {int(r) for r in np.flatnonzero(np.any(sub.target != problem.target, axis=1))}


def _plan(sub, lattice=None):
    return Plan("complete", [sub.start.copy(), sub.target.copy()], 1, 1, [], "", {}, lattice=lattice)


def _coarse(problem):
    """On the problem's lattice neither robot 0 nor robot 1 can reach its target."""
    def attempt(sub):
        off = _off(problem, sub)
        if 0 not in off:
            return [0], "coarse"
        return _plan(sub) if 1 in off else ([1], "coarse")
    return attempt


def test_the_finer_lattice_puts_back_the_robots_it_has_a_plan_for():
    problem = parse_problem(TRIANGLE)
    tried = []

    def finer(sub):  # on the finer lattice only robot 1 stays off target
        tried.append(sorted(_off(problem, sub)))
        return _plan(sub, (24,)) if 1 in _off(problem, sub) else ([1, 2], "finer")

    r = partial_search(problem, [0], "coarse", _coarse(problem), finer=finer)
    assert tried == [[], [1]]  # all put back at once, then all but the finer certificate's robot
    assert [e.robot for e in r.off_target] == [1] and r.on_target == 2
    assert r.stats.finer_put_back == [0] and r.stats.finer_attempts == 2
    assert r.plan.lattice == (24,)
    assert not r.optimal and r.on_target_bound == 3  # the coarse lattice's bound says nothing there
    assert r.off_target[0].certificate.members == (1,)  # the reason is still the coarse certificate


def test_without_a_finer_plan_or_budget_the_coarse_answer_stands():
    problem = parse_problem(TRIANGLE)
    def refused(sub):
        return [0, 1], "finer"

    def out_of_time(sub):
        raise BudgetExceeded("timeout")

    for finer in (refused, out_of_time, None):
        r = partial_search(problem, [0], "coarse", _coarse(problem), finer=finer)
        assert sorted(e.robot for e in r.off_target) == [0, 1] and r.plan.lattice is None
        assert r.stats.finer_put_back == [] and r.optimal and r.on_target_bound == 1


def test_sub_problems_run_one_descent_in_the_whole_problems_direction():
    from supcoord.planning import Local, solve
    from supcoord.planning.windows import WindowObserver

    class Count(WindowObserver):
        descents = 0

        def descended(self, steps):
            Count.descents += 1

    plan = solve(parse_problem(TRIANGLE), route=Local(observer=Count()), improve=0)
    assert plan.status == "partial" and plan.stats["direction"] in ("forward", "reverse")
    # both ways for the whole problem; one way for each sub-problem (both ways each: 2 + 2 per attempt)
    assert Count.descents < 2 * (1 + plan.stats["partial"]["attempts"])


def test_a_lattice_finer_again_is_tried_where_the_first_puts_no_robot_back():
    problem = parse_problem(TRIANGLE)
    tried = []

    def first(sub):  # the first finer lattice certifies both robots off target again
        tried.append(("first", sorted(_off(problem, sub))))
        return [0, 1], "finer"

    def again(sub):  # the lattice finer again has a plan with robot 0 on target
        tried.append(("again", sorted(_off(problem, sub))))
        return _plan(sub, (36,)) if 1 in _off(problem, sub) else ([1, 2], "finer again")

    r = partial_search(problem, [0], "coarse", _coarse(problem), finer=(first, again))
    assert tried == [("first", []), ("again", []), ("again", [1])]
    assert [e.robot for e in r.off_target] == [1] and r.on_target == 2 and r.plan.lattice == (36,)
    assert r.stats.finer_put_back == [0] and r.stats.finer_attempts == 3
    assert not r.optimal and r.on_target_bound == 3


def test_the_lattice_finer_again_is_not_tried_where_the_first_puts_a_robot_back():
    problem = parse_problem(TRIANGLE)

    def first(sub):
        return _plan(sub, (24,)) if 1 in _off(problem, sub) else ([1], "finer")

    def again(sub):
        raise AssertionError("the lattice finer again is not needed")

    r = partial_search(problem, [0], "coarse", _coarse(problem), finer=[first, again])
    assert r.stats.finer_put_back == [0] and r.plan.lattice == (24,)


def test_the_planner_hands_step_4_the_finer_lattice_and_the_one_finer_again():
    from types import SimpleNamespace

    from supcoord.planning import planner
    from supcoord.planning.solve_stats import Refined

    ab = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7}
    p = parse_problem({"layout": {"kind": "hex", "rings": 1, "pitch": 22.4}, "kinematics": ab,
                       "collision": {"buffer": 1.0}, "start": [[0, 0]] * 7, "target": [[6, 6]] * 7})

    def verdict(refined):
        return SimpleNamespace(stats=SimpleNamespace(refined=refined))

    attempts = planner._finer_attempt(p, verdict(Refined("infeasible", lattice=(18, 10))), None, None)
    assert len(attempts) == 2  # 18 x 10, then 27 x 15
    assert [c.cell_contents for a in attempts for c in a.__closure__ if isinstance(c.cell_contents, tuple)] \
        == [(18, 10), (27, 15)]
    for refined in (None, Refined("unknown", lattice=(18, 10)), Refined("not searched")):
        assert planner._finer_attempt(p, verdict(refined), None, None) == ()


def test_a_neighbourhood_certified_alone_stays_off_target_without_planning_the_rest():
    problem = parse_problem(TRIANGLE)
    whole, alone_calls = [], []

    def finer(sub):
        whole.append(sorted(_off(problem, sub)))
        return _plan(sub, (24,)) if 1 in _off(problem, sub) else ([1, 2], "finer")

    def alone(sub, members):  # robot 1 with its neighbours alone has no plan on the finer lattice
        alone_calls.append((sorted(members), sorted(_off(problem, sub))))
        return ([1, 2], "alone") if 1 in members and 1 not in _off(problem, sub) else None

    finer.alone = alone
    r = partial_search(problem, [0], "coarse", _coarse(problem), finer=finer)
    assert whole == [[1]]  # the whole problem planned once, with robot 1 already kept off target
    assert alone_calls == [([0, 1, 2], []), ([0, 1, 2], [1])]
    assert [e.robot for e in r.off_target] == [1] and r.stats.finer_put_back == [0]
    assert r.stats.finer_attempts == 1 and r.stats.finer_alone == 2
    assert r.stats.to_json()["finer_alone"] == 2


def test_the_planners_neighbourhood_names_the_whole_problems_robots(monkeypatch):
    from types import SimpleNamespace

    from supcoord.planning import planner
    from supcoord.planning.windows import Certificate

    ab = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7}
    p = parse_problem({"layout": {"kind": "hex", "rings": 1, "pitch": 22.4}, "kinematics": ab,
                       "collision": {"buffer": 1.0}, "start": [[0, 0]] * 7, "target": [[6, 6]] * 7})
    seen = []

    def fake_solve(sub, settings, budget):
        seen.append((sub.n, sub.kinematics.n_positions))
        return SimpleNamespace(certificate=Certificate([1, 2], "window"), plan=None)

    monkeypatch.setattr(planner, "_solve", fake_solve)
    attempt = planner._lattice_attempt(p, (18, 10), None, None)
    assert attempt.alone(p, [0, 3, 5]) == ([3, 5], "window")  # sub-problem robots 1, 2 are robots 3, 5
    assert seen == [(3, 180)]  # the three robots alone, on the 18 x 10 lattice


def test_a_search_that_puts_every_robot_back_answers_a_complete_plan(monkeypatch):
    """Step 4 may put back the last robot off target on a lattice finer than any the whole
    problem was searched on: the answer is then a complete plan, validated as one (it was a
    'partial' plan with no robot off target, which the validator refused: an internal error)."""
    import time

    from supcoord.planning import planner
    from supcoord.planning.partial import PartialResult, PartialStats
    from supcoord.planning.windows import Certificate
    from supcoord.bdd.budget import Budget
    from supcoord.problems.validate import validate_plan

    ab = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7}
    p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [60, 0], [120, 0]]}, "kinematics": ab,
                       "collision": {"buffer": 1.0}, "start": [[0, 0]] * 3, "target": [[6, 6], [3, 2], [9, 5]]})
    settings = planner._settings("local", "auto", None, 0, None, None, None, "independent")
    solved = planner._solve(p, settings, Budget())
    assert solved.plan.status == "complete"
    verdict = planner.Solved(solved.plan, solved.stats, Certificate([0], "window"))
    found = PartialResult(solved.plan, (), True, 3, 3, PartialStats(method="exact", finer_put_back=[0]))
    monkeypatch.setattr(planner, "partial_search", lambda *args: found)
    out = planner._partial(p, settings, Budget(), verdict, time.perf_counter())
    assert out.status == "complete" and out.off_target == () and out.on_target is None
    assert validate_plan(p, out).valid
    assert out.stats["partial"]["finer_put_back"] == [0]
