"""Where planning's caches live: one :class:`PlanningCache` per collision geometry.

The planner reads the same derived tables many times: the blocked tables of
:mod:`.guards`, their lazily decided entries, the conflict graph, the simultaneous motions
of :mod:`.descent` and the free tables of :mod:`.optimum`.  Each depends only on the
problem's collision geometry (its :class:`~supcoord.geometry.collision.CollisionTables`:
layout, kinematics, buffers, obstacles and robots held), never on its start or target.
So the cache is held per tables object, in a mapping owned by this module that drops it
with its tables:

- a problem and its copies with another start or target (``problems.plan.exchanged``)
  share one cache, as they share their tables;
- the cache goes when the tables go (nothing in a cache refers to a problem or its tables,
  which would keep them alive);
- nothing is written onto the :class:`~supcoord.problems.problem.Problem`.

:func:`caches_for` is the one way in; the functions of :mod:`.guards`, :mod:`.descent` and
:mod:`.optimum` keep their signatures and look their cache up themselves.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..geometry.table_store import PackedTables
from ..problems.problem import Problem

__all__ = ["PlanningCache", "BlockedEntryCache", "Adjacency", "caches_for", "BLOCKED_CACHE_BYTES", "ENTRY_CACHE"]

#: ``adj[p] = [(k, q, mover), …]``: pair ``k = (p, q)`` with ``p`` its member ``mover`` (0: ``a``, 1: ``b``)
Adjacency = list[list[tuple[int, int, int]]]

#: lazy tables' blocked entries remembered (:class:`BlockedEntryCache`; emptied when full)
ENTRY_CACHE = 2_000_000
#: bytes of blocked tables kept unpacked (all are kept bit-packed: :func:`.guards.blocked_bits`)
BLOCKED_CACHE_BYTES = 256 * 2**20


class BlockedEntryCache:
    """Remembered blocked entries of lazy tables, one integer key per entry:
    ``code(problem, pair, mover) + (move · P + mover_at) · P + other_at`` with ``P`` positions
    (pairs of equal geometry share a code, :meth:`Problem.pair_geometry_key`).  It holds no
    reference to a problem or its tables (which would keep them, and so the cache, alive).

    Parameters
    ----------
    n_positions : int
        Positions of one robot (``P``).
    n_moves : int
        Moves of one robot.
    """

    def __init__(self, n_positions: int, n_moves: int):
        self.n_pos = n_positions
        self.span = n_moves * n_positions ** 2
        self.hits: dict[int, bool] = {}
        self._geometry: dict[tuple, int] = {}
        self._codes: dict[tuple[int, int], int] = {}

    def code(self, problem: Problem, pair: int, mover: int) -> int:
        """The key offset of pair ``pair``'s blocked table with mover ``mover`` in ``problem``."""
        out = self._codes.get((pair, mover))
        if out is None:
            g = self._geometry.setdefault(problem.pair_geometry_key(pair) + (mover,), len(self._geometry))
            out = self._codes[pair, mover] = g * self.span
        return out


@dataclass(eq=False)
class PlanningCache:
    """Everything planning derives from one collision geometry and keeps (module docstring).

    Attributes
    ----------
    blocked : PackedTables
        The blocked tables (:func:`.guards.blocked_table`), bit-packed, by pair geometry key
        and mover.
    entries : BlockedEntryCache or None
        Lazy tables' blocked entries decided so far (:func:`.guards.blocked_entries`).
    successors : tuple of two int arrays, or None
        ``(nxt, rev)``: the flat position after move ``m`` from ``i`` (−1 past a hard stop)
        and the move back of every move.
    pair_graph, conflict_graph : Adjacency or None
        :func:`.guards.pair_graph` and :func:`.guards.conflict_graph`.
    motions : dict
        :func:`.descent.motion_free` verdicts (True: the motion collides) by pair geometry,
        poses and deltas.
    free_simultaneous : dict
        :mod:`.optimum`'s ``F[u, v, i, j]`` tables by pair geometry key.
    orders : dict
        Variable orders of the conflict graph (:mod:`.graph_order`) by kind and member set:
        a window grown by one robot is a new member set, so a new key.
    """

    blocked: PackedTables = field(default_factory=lambda: PackedTables(BLOCKED_CACHE_BYTES))
    entries: BlockedEntryCache | None = None
    successors: tuple[NDArray[np.int_], NDArray[np.int_]] | None = None
    pair_graph: Adjacency | None = None
    conflict_graph: Adjacency | None = None
    motions: dict[tuple, bool] = field(default_factory=dict)
    free_simultaneous: dict[tuple, NDArray[np.bool_]] = field(default_factory=dict)
    orders: dict[tuple, tuple[int, ...]] = field(default_factory=dict)


#: the caches by ``id`` of their tables; each entry is dropped when its tables are collected
#: (:func:`weakref.finalize`): a plain dictionary of integers, as fast as an attribute
#: lookup, which the planner's hot readers need
_CACHES: dict[int, PlanningCache] = {}


def caches_for(problem: Problem) -> PlanningCache:
    """The :class:`PlanningCache` of ``problem``'s collision geometry, made on first use.

    Parameters
    ----------
    problem : Problem
        The problem; its cache is keyed by its collision tables (:meth:`Problem.tables`),
        which its copies with another start or target share.

    Returns
    -------
    PlanningCache
        The same object for every call with the same tables.

    Examples
    --------
    >>> from supcoord.problems.presets import preset_problem
    >>> from supcoord.problems.plan import exchanged
    >>> problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5)
    >>> caches_for(problem) is caches_for(exchanged(problem))
    True
    """
    tables = problem.tables()
    out = _CACHES.get(id(tables))
    if out is None:
        out = _CACHES[id(tables)] = PlanningCache()
        weakref.finalize(tables, _CACHES.pop, id(tables), None)
    return out
