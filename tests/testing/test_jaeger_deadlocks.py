"""The bookkeeping of jaeger's decollision and deadlock resolution as ``benchmarks/jaeger_deadlocks.py``
re-implements it (jaeger 1.9.1 ``configuration.py`` ``get_paths``/``_resolve_deadlocks``,
``kaiju.py`` ``decollide``), on a scripted grid instead of kaiju's."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

_PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "jaeger_deadlocks.py"
_spec = importlib.util.spec_from_file_location("jaeger_deadlocks", _PATH)
jd = sys.modules.setdefault("jaeger_deadlocks", importlib.util.module_from_spec(_spec))
_spec.loader.exec_module(jd)


class ScriptedGrid:
    """Robots 0..n-1; ``blocking`` robots deadlock the plan while they keep their targets, and
    ``deadlocked`` are the robots kaiju then reports; ``collided`` robots collide until redrawn
    (``sticky`` ones stay collided)."""

    def __init__(self, n=8, blocking=(), deadlocked=(), offline=(), collided=(), sticky=(), redraw_collides=False):
        self.n, self.blocking, self.deadlocked = n, set(blocking), tuple(deadlocked)
        self.offline, self.collided, self.sticky = set(offline), set(collided), set(sticky)
        self.redraw_collides = redraw_collides
        self.moved: set[int] = set()
        self.saved = set()
        self.calls: list[tuple] = []
        self.plans = 0

    def robots(self):
        return list(range(self.n))

    def is_offline(self, r):
        return r in self.offline

    def collided_robots(self):
        return sorted(self.collided)

    def is_collided(self, r):
        return r in self.collided

    def set_xy_uniform(self, r):
        self.calls.append(("xy", r))
        self.moved.add(r)
        if self.redraw_collides:
            self.collided.add(r)

    def decollide_robot(self, r):
        self.calls.append(("decollide", r))
        self.moved.add(r)
        if r not in self.sticky:
            self.collided.discard(r)

    def save(self):
        self.saved = set(self.moved)

    def restore(self):
        self.calls.append(("restore",))
        self.moved = set(self.saved)

    def plan(self):
        self.plans += 1
        stuck = self.blocking - self.moved
        at = frozenset(r for r in range(self.n) if not (stuck and r in self.deadlocked))
        return jd.PathResult(bool(stuck), self.deadlocked if stuck else (), at)


def test_a_plan_without_deadlock_keeps_every_robot_on_target():
    g = ScriptedGrid(offline={7})
    out = jd.get_paths(g, np.random.RandomState(0))
    assert out.error == "" and out.attempts == 0 and g.plans == 1
    assert out.on_target == list(range(7))          # the offline robot has no target


def test_a_deadlock_that_never_clears_plans_six_times_moves_five_robots_and_raises():
    g = ScriptedGrid(n=30, blocking={99}, deadlocked=tuple(range(10, 30)))
    out = jd.get_paths(g, np.random.RandomState(1))
    assert g.plans == jd.N_RETRIES + 1 == 6
    assert out.attempts == 6 and "retries has been exhausted" in out.error
    assert [c for c in g.calls if c[0] == "xy"] == [("xy", r) for r in out.unlocked]
    assert 1 <= len(out.unlocked) <= 5 and set(out.unlocked) <= set(range(10, 30))
    # what the last plan would give: not deadlocked, not moved
    assert out.on_target == list(range(10))


def test_the_robot_moved_is_numpys_choice_among_the_deadlocked():
    g = ScriptedGrid(n=30, blocking={99}, deadlocked=tuple(range(10, 30)))
    out = jd.get_paths(g, np.random.RandomState(7))
    rng = np.random.RandomState(7)
    expected = []
    for _ in range(5):
        r = int(rng.choice(list(range(10, 30))))
        if r not in expected:
            expected.append(r)
    assert out.unlocked == expected


def test_moving_the_blocking_robot_clears_the_deadlock_and_only_moved_robots_lose_targets():
    g = ScriptedGrid(n=6, blocking={3}, deadlocked=(3,))
    out = jd.get_paths(g, np.random.RandomState(0))
    assert out.error == "" and out.unlocked == [3] and out.attempts == 1 and g.plans == 2
    assert out.on_target == [0, 1, 2, 4, 5]
    assert g.calls[:2] == [("restore",), ("xy", 3)]   # the grid is restored before the robot moves


def test_force_goes_on_after_the_retries_until_a_plan_succeeds():
    g = ScriptedGrid(n=12, blocking=set(range(4, 12)), deadlocked=tuple(range(4, 12)))
    out = jd.get_paths(g, np.random.RandomState(3), force=True)
    assert out.error == "" and set(out.unlocked) == set(range(4, 12)) and out.attempts > 5
    assert out.on_target == [0, 1, 2, 3]
    g = ScriptedGrid(n=12, blocking=set(range(4, 12)), deadlocked=tuple(range(4, 12)))
    assert "exhausted" in jd.get_paths(g, np.random.RandomState(3)).error


def test_a_moved_robot_that_lands_collided_is_decollided_unless_offline():
    g = ScriptedGrid(n=5, blocking={2}, deadlocked=(2,), redraw_collides=True)
    out = jd.get_paths(g, np.random.RandomState(0))
    assert ("decollide", 2) in g.calls and out.error == ""
    g = ScriptedGrid(n=5, blocking={2}, deadlocked=(2,), offline={2}, redraw_collides=True)
    out = jd.get_paths(g, np.random.RandomState(0))
    assert ("decollide", 2) not in g.calls and out.offline_moved == [2]
    g = ScriptedGrid(n=5, blocking={2}, deadlocked=(2,), redraw_collides=True, sticky={2})
    assert jd.get_paths(g, np.random.RandomState(0)).error == "Cannot decollide deadlocked robot."


def test_decollision_moves_the_lowest_priority_first_skips_offline_and_loses_those_targets():
    g = ScriptedGrid(n=6, collided={1, 2, 4, 5}, offline={5})
    g.collided_robots = lambda: sorted(g.collided)
    out = jd.get_paths(g, np.random.RandomState(0), priority_order=[1, 4, 2])
    assert [c[1] for c in g.calls if c[0] == "decollide"] == [2, 4, 1]   # last in priority first
    assert out.decollided == [2, 4, 1] and "Failed decolliding grid." == out.error  # 5 stays collided
    g = ScriptedGrid(n=6, collided={1, 4})
    out = jd.get_paths(g, np.random.RandomState(0), priority_order=[0, 1, 2, 3, 4, 5])
    assert out.error == "" and out.decollided == [4, 1] and out.on_target == [0, 2, 3, 5]


def test_a_robot_that_stays_collided_raises_as_jaeger_does():
    g = ScriptedGrid(n=4, collided={2}, sticky={2})
    out = jd.get_paths(g, np.random.RandomState(0))
    assert out.error == "Failed decolliding positioner 2." and out.last is None and out.on_target == []


@pytest.mark.parametrize("retries", [0, 2])
def test_the_number_of_retries_bounds_the_plans(retries):
    g = ScriptedGrid(n=10, blocking={99}, deadlocked=(1, 2, 3))
    out = jd.get_paths(g, np.random.RandomState(0), n_retries=retries)
    assert g.plans == retries + 1 and "exhausted" in out.error
