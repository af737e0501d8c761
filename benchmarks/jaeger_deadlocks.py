"""jaeger's decollision and deadlock resolution, re-implemented from its source (no kaiju needed here).

SDSS-V's robot controller jaeger (PyPI ``jaeger`` 1.9.1; sdss/jaeger) plans a configuration's
paths in ``BaseConfiguration.get_paths`` (``jaeger/target/configuration.py``, lines 293-456):

1. robots start at their targets, the destination is the folded lattice; offline robots are held;
2. ``decollide`` (``jaeger/kaiju.py``, lines 141-235; ``simple=False``, no grid fallback, the
   assigned robots as ``priority_order``): the collided robots sorted by priority, each still
   collided and not offline redrawn by kaiju's ``decollideRobot`` (``setXYUniform`` up to 1000
   times); a robot that stays collided raises ``JaegerError``; the redrawn robots lose their
   targets ("decollided");
3. ``_resolve_deadlocks`` (``configuration.py``, lines 458-537; ``n_retries=5``, ``force=False``,
   what jaeger's ``configuration load`` command runs): plan (``get_path_pair``, kaiju's
   ``pathGenMDP2`` or ``pathGenGreedy``); if kaiju fails, ``attempt += 1``; past ``n_retries``
   attempts raise ``TrajectoryError`` (with ``force=True``: log and go on); otherwise pick one
   deadlocked robot with ``numpy.random.choice(deadlocks)``, restore the grid as it was before
   planning, move that robot to a random position (``setXYUniform``), and if it is then
   collided and not offline, ``decollideRobot`` it (still collided: ``TrajectoryError``); the
   moved robots lose their targets. A path without failure ends the loop.

So with the defaults kaiju plans at most 6 times and at most 5 robots are moved; when the 6th
plan still fails jaeger raises and the configuration is not run.

This module holds that bookkeeping over an abstract grid (:class:`Grid`), so that it can be
tested without kaiju; ``kaiju_side.py jaeger`` gives it kaiju's grid. jaeger draws with
numpy's global generator and seeds each reloaded grid from the clock; here the generator is a
seeded ``numpy.random.RandomState`` (the same ``choice``) and the grid's seeds are the
caller's, so that a run can be repeated.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

#: jaeger's defaults: ``get_paths(n_deadlock_retries=5, force=False)``
N_RETRIES = 5


@dataclass(frozen=True)
class PathResult:
    """One path generation: kaiju's ``didFail``, ``deadlockedRobots()`` and the robots that end
    at their destination (``score() == 0``)."""

    did_fail: bool
    deadlocks: tuple[int, ...]
    at_destination: frozenset[int]


class Grid(Protocol):
    """What jaeger does to kaiju's grid. ``plan`` plans from the saved state (jaeger dumps the
    grid and plans on a copy); ``restore`` brings the saved state back; ``save`` keeps the
    current one."""

    def robots(self) -> list[int]: ...
    def is_offline(self, robot: int) -> bool: ...
    def collided_robots(self) -> list[int]: ...
    def is_collided(self, robot: int) -> bool: ...
    def set_xy_uniform(self, robot: int) -> None: ...
    def decollide_robot(self, robot: int) -> None: ...
    def plan(self) -> PathResult: ...
    def restore(self) -> None: ...
    def save(self) -> None: ...


@dataclass
class JaegerOutcome:
    """What jaeger's ``get_paths`` ends with, and what it did on the way.

    ``error`` is the exception jaeger raises (``""`` when it returns a trajectory); ``on_target``
    counts the robots at their own targets at the end of the last plan: not offline, not moved
    by the decollision or the deadlock resolution, and at their destination (when jaeger raises,
    this is what the last plan would have given had it run anyway).
    """

    error: str = ""
    attempts: int = 0
    decollided: list[int] = field(default_factory=list)
    unlocked: list[int] = field(default_factory=list)
    offline_moved: list[int] = field(default_factory=list)
    deadlocks_per_attempt: list[int] = field(default_factory=list)
    last: PathResult | None = None
    on_target: list[int] = field(default_factory=list)

    @property
    def reassigned(self) -> set[int]:
        """Robots whose targets jaeger gave up (``decollided`` and ``unlocked``)."""
        return set(self.decollided) | set(self.unlocked)


class JaegerError(Exception):
    """jaeger's ``JaegerError`` / ``TrajectoryError`` (the message is jaeger's)."""


class TimeLimit(JaegerError):
    """The benchmark's time limit stopped the loop before jaeger ended (not jaeger's)."""


def decollide(grid: Grid, priority_order: list[int], moved: list[int]) -> None:
    """jaeger ``kaiju.decollide(simple=False, decollide_grid_fallback=False, priority_order)``;
    the robots moved are appended to ``moved`` (also when it raises :class:`JaegerError`, as
    jaeger does)."""
    collided = sorted(grid.collided_robots(),
                      key=lambda x: len(priority_order) - priority_order.index(x) if x in priority_order else -1)
    for robot in collided:
        if grid.is_collided(robot):
            if grid.is_offline(robot):
                continue
            grid.decollide_robot(robot)
            moved.append(robot)
            if grid.is_collided(robot):
                raise JaegerError(f"Failed decolliding positioner {robot}.")
    if grid.collided_robots():
        raise JaegerError("Failed decolliding grid.")


def resolve_deadlocks(grid: Grid, rng, out: JaegerOutcome, n_retries: int = N_RETRIES, force: bool = False,
                      max_attempts: int = 1000) -> None:
    """jaeger ``BaseConfiguration._resolve_deadlocks``, recording into ``out``.

    ``rng`` has numpy's ``choice`` (``numpy.random.RandomState``). ``max_attempts`` only bounds
    ``force=True``, which jaeger loops until a plan succeeds. Raises :class:`JaegerError` where
    jaeger raises ``TrajectoryError``.
    """
    while True:
        res = grid.plan()
        out.last = res
        out.deadlocks_per_attempt.append(len(res.deadlocks))
        if not res.did_fail:
            return
        out.attempts += 1
        if n_retries < 0:
            raise JaegerError(f"Failed generating a valid trajectory. {len(res.deadlocks)} deadlocks were found.")
        if out.attempts > n_retries:
            msg = (f"Attempt {out.attempts}: {len(res.deadlocks)} deadlocks remain but "
                   "the number of retries has been exhausted.")
            if not force or out.attempts >= max_attempts:
                raise JaegerError(msg)
        if not res.deadlocks:  # numpy.random.choice([]) raises in jaeger
            raise JaegerError("ValueError: 'a' cannot be empty unless no samples are taken")
        to_move = int(rng.choice(list(res.deadlocks)))
        grid.restore()
        grid.set_xy_uniform(to_move)
        if grid.is_offline(to_move) and to_move not in out.offline_moved:
            out.offline_moved.append(to_move)
        if grid.is_collided(to_move) and not grid.is_offline(to_move):
            grid.decollide_robot(to_move)
            if grid.is_collided(to_move):
                raise JaegerError("Cannot decollide deadlocked robot.")
        if to_move not in out.unlocked:
            out.unlocked.append(to_move)
        grid.save()


def get_paths(grid: Grid, rng, priority_order: list[int] | None = None, n_retries: int = N_RETRIES,
              force: bool = False) -> JaegerOutcome:
    """jaeger ``BaseConfiguration.get_paths(decollide=True, simple_decollision=False,
    resolve_deadlocks=True)`` on ``grid`` (robots at their targets): decollide, save, resolve
    deadlocks; the outcome counts the robots left on target. Never raises: jaeger's exception
    is ``outcome.error``."""
    out = JaegerOutcome()
    order = list(grid.robots()) if priority_order is None else list(priority_order)
    try:
        decollide(grid, order, out.decollided)
        grid.save()
        resolve_deadlocks(grid, rng, out, n_retries=n_retries, force=force)
    except JaegerError as exc:
        out.error = str(exc)
    if out.last is not None:
        out.on_target = sorted(r for r in out.last.at_destination
                               if not grid.is_offline(r) and r not in out.reassigned)
    return out
