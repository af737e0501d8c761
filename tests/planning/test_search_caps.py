"""The window search under a node cap (``planning/search.py``).

A cap only decides how much work a window may take: when an image exceeds it, that side of
the bidirectional search stops and the other goes on alone; the search gives up only when
both have stopped.  Whatever the cap, an answer is the uncapped one (the same distance, or
the same "unreachable"), and the stopped side is really reached on these cases.
"""

import pytest

from supcoord.planning import search as search_module
from supcoord.planning.guards import conflict_graph
from supcoord.planning.model import CoordinationModel
from supcoord.planning.search import WindowBudget, search, shortest_moves
from supcoord.problems.random import random_problem

AB = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 6, "beta_steps": 4, "beta_range": [0, 180]}


@pytest.mark.timeout(120)
def test_a_capped_search_answers_as_the_uncapped_one_or_gives_up(monkeypatch):
    stopped = []
    real = search_module.image

    def image(S, x, limit=None):
        try:
            return real(S, x, limit)
        except search_module._ImageTooLarge:
            stopped.append(limit)
            raise

    monkeypatch.setattr(search_module, "image", image)
    answered_after_a_stop = 0
    for pitch, seed in ((16.0, 0), (16.0, 2), (16.0, 3), (20.0, 2), (20.0, 4)):
        p = random_problem({"kind": "hex", "rings": 1, "pitch": pitch}, AB, 1.5, seed=seed)
        conflict_graph(p)
        members = [0, 1, 2, 3, 4]
        model = CoordinationModel(p, order="cutwidth", members=members)
        for frozen in (None, p.start):  # the others removed, or frozen at the start
            S = model.system(members, frozen, init=p.start)
            for goal_members in ([0], [0, 1]):  # loose goals leave the others free: big backward images
                goal = model.state(goal_members, p.target) & S.invariant
                exact = search(S, goal)
                for cap in (30, 100, 200, 300, 1000):
                    before = len(stopped)
                    try:
                        res = search(S, goal, max_nodes=cap)
                    except WindowBudget:
                        continue
                    assert res.distance == exact.distance, (pitch, seed, goal_members, cap)
                    if res.distance is not None:
                        assert len(shortest_moves(S, res, p.start)) == exact.distance
                    answered_after_a_stop += len(stopped) > before
    assert stopped, "no image ever exceeded a cap: the route is not reached"
    assert answered_after_a_stop >= 5, answered_after_a_stop
