"""The pattern databases of :mod:`.settled_bound` inside the projection refinement's sets:
a tighter lower bound for the A* where the sets are known.

The bound of :mod:`.settled_bound` relaxes the coupled model to the arms of one group with
every other arm removed, so an arm outside the group never blocks a move of the group.
Projection refinement (:mod:`.settled_refine`) over-approximates, on every closed
neighbourhood ``H``, the positions of ``H``'s arms on some path from the start to the
target (backward sets: from which the target is reachable; both: reachable from the start
as well).  Restrict the relaxation of a group ``P`` by them:

- keep only the configurations of ``P`` that every set admits (projected onto ``P``), a
  move leaving and reaching one;
- let ``P_i ∈ P`` turn in direction ``s`` only where some positions of its neighbours
  outside ``P``, admitted with ``P``'s by the set of ``i``'s neighbourhood, let it
  (:meth:`~.settled_refine._Refiner.enabled_on`, the rule of the refinement itself).

**Admissible and consistent on the states the A* keeps.**  The A* expands only states
reachable from ``settle(q0)`` and, when the sets are known, inside them.  A shortest path
from such a state ``x`` to the target joins the start to the target through ``x``, so
every configuration on it lies in every set (for the backward sets: each reaches the
target); each of its moves of an arm of ``P`` is a move of the restricted relaxation
(the concrete neighbours' positions are the witness of the existential, and the group's
own rule is that of :mod:`.settled_bound`) of at least the cost charged there.  So
``d_P`` restricted is at most the weight left, the sum over the disjoint groups too (one
arm moves per event), and along an edge between two kept states the restricted edge
exists, so it drops by at most the edge's weight.  It is never below the unrestricted
bound (fewer moves, fewer configurations).  Where a restricted ``d_P`` is infinite no path
from the start to the target passes there: the A* never expands such a state, which is
what the sets already say.

``tests/paper/test_settled_sets_bound.py`` checks it against the exact ranks of an
explicit oracle written from the plant's rules on random instances.

References
----------
- J. C. Culberson, J. Schaeffer, Pattern databases, Computational Intelligence 14(3), 1998.
- P. Cousot, R. Cousot, Abstract interpretation, POPL 1977 (the sets over-approximate).
"""

from __future__ import annotations

import copy

import numpy as np

from .settled_bound import PatternBound
from .settled_refine import Projections, _Refiner

__all__ = ["within_sets"]


def within_sets(bound: PatternBound, proj: Projections) -> PatternBound:
    """The bound of ``bound``'s groups, each database recomputed inside ``proj``'s sets
    (module docstring): admissible and consistent on the configurations ``proj`` admits.

    Parameters
    ----------
    bound : PatternBound
        The unrestricted databases (their groups are kept).
    proj : Projections
        Sets of :func:`~.settled_refine.refine` (backward, or forward within backward).

    Returns
    -------
    PatternBound
        A copy whose ``tables`` are the restricted distances (each at least ``bound``'s).

    Examples
    --------
    >>> from supcoord.paper.coupled import CoupledModel
    >>> from supcoord.paper.run import coupled_instance
    >>> from supcoord.paper.settled_refine import refine
    >>> model = CoupledModel(coupled_instance(5, 8, 0))
    >>> plain = PatternBound(model)
    >>> tight = within_sets(plain, refine(model, forward=False))
    >>> plain.value(model.inst.start) <= tight.value(model.inst.start)
    True
    """
    work = _Refiner(bound.model, proj.groups, proj.forward)
    out = copy.copy(bound)
    out.tables = []
    for group in bound.groups:
        key = tuple(group)
        shape = (work.n,) * len(group)
        within = work.inside(proj.sets, key).reshape(-1)

        def outside(a: int, sign: int, key: tuple[int, ...] = key, shape: tuple[int, ...] = shape) -> np.ndarray:
            return np.broadcast_to(work.enabled_on(proj.sets, key, key[a], sign), shape).reshape(-1)

        out.tables.append(bound._table(group, within, outside))
    return out
