"""A forcing string of the coupled model found greedily, and its check by replay.

The A* of :mod:`.settled` proves the rank; a witness alone proves the verdict.  By the
theorem of :mod:`.settled`, every path from ``settle(q0)`` to the target ``T`` in the
graph of settled states is a strategy that forces ``T``: the controller fires the path's
controllable events, each once no uncontrollable event is pending, and whatever order the
environment fires its pending events in, they end in the same settled state after the
same number of events.  So the string of such a path (pending events fired smallest
first, as :func:`~supcoord.synthesis.witness` reads them) proves ``q0`` forcible, and its
length bounds ``rank(q0)`` from above.

:func:`greedy_witness` looks for such a path by greedy best-first search on the explicit
settled states, ordered by the pattern-database bound ``h`` of :mod:`.settled_bound`
(then by the events spent), up to a number of expanded states.  It proves nothing when
it gives up.  :func:`replay` checks a string against the coupled plant's own rules
(:meth:`~.coupled.CoupledModel.successors`) under preemptive semantics, independently of
how the string was found: every event defined where it fires, a controllable event only
where no uncontrollable one is pending, the last state the target with every level 0.
:func:`greedy_witness` returns only strings that :func:`replay` accepts.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (forcibility under preemption).
- J. Pearl, Heuristics, Addison-Wesley 1984 (greedy best-first search).
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import InputError, ModelError
from .coupled import CoupledModel
from .events import decode_label
from .settled_bound import UNREACHABLE, PatternBound
from .settled_graph import State, settle, successor_events

__all__ = ["GREEDY_LIMIT", "POSITION_LIMIT", "GreedyWitness", "greedy_witness", "position_witness", "replay"]

#: settled states :func:`greedy_witness` expands at most before it gives up: about 3 s of CPU
#: at 19 positioners, where 6 of the 7 strings found over seeds 0-29 took fewer (survey_coupled.py)
GREEDY_LIMIT = 2_000
#: configurations :func:`position_witness` expands at most: about 10 s of CPU at 19
#: positioners; seed 6 took 8,397 (survey_coupled.py)
POSITION_LIMIT = 50_000
#: expansions between two calls of a search's ``check`` (a few milliseconds at 19 positioners)
CHECK_EVERY = 16


@dataclass(frozen=True)
class GreedyWitness:
    """A forcing string of the coupled model, checked by :func:`replay`.

    Attributes
    ----------
    witness : tuple of str
        The events, controllable and uncontrollable, from ``q0`` to the target.
    length : int
        ``len(witness)``: an upper bound on ``rank(q0)`` (events).
    expanded : int
        Settled states the search expanded.
    """

    witness: tuple[str, ...]
    length: int
    expanded: int


def _settled(model: CoupledModel, state: State, path: list[str]) -> State:
    """Fire the pending uncontrollable events of ``state``, smallest first, onto ``path``."""
    while True:
        pending = successor_events(model, state, controllable=False)
        if not pending:
            return state
        name, state = pending[0]
        path.append(name)


def replay(model: CoupledModel, witness: list[str] | tuple[str, ...]) -> int:
    """Check that ``witness`` forces the target of the coupled model under preemptive semantics.

    Parameters
    ----------
    model : CoupledModel
        The instance; its target must have no arm in another's safety zone.
    witness : sequence of str
        Event names, from ``q0``.

    Returns
    -------
    int
        The number of events: an upper bound on ``rank(q0)``.

    Raises
    ------
    ModelError
        If an event is not defined where it fires, a controllable event fires while an
        uncontrollable one is pending, or the string does not end at the target.

    Examples
    --------
    >>> from supcoord.paper.run import coupled_instance
    >>> model = CoupledModel(coupled_instance(3, 8, 0))
    >>> replay(model, ["71", "71", "81", "81", "81", "81", "91", "71"])
    8
    >>> replay(model, ["71", "81"])
    Traceback (most recent call last):
    ...
    supcoord.errors.ModelError: the witness does not end at the target with every level 0
    """
    size = model.inst.size
    state: State = (tuple(model.inst.start), (0,) * size)
    for step, name in enumerate(witness):
        pending = successor_events(model, state, controllable=False)
        allowed = dict(pending or successor_events(model, state, controllable=True))
        if name not in allowed:
            why = "an uncontrollable event is pending" if pending else "it is not defined there"
            raise ModelError(f"event {name} at step {step + 1} of the witness cannot fire: {why}", value=name)
        state = allowed[name]
    if state != (tuple(model.inst.target), (0,) * size):
        raise ModelError("the witness does not end at the target with every level 0", value=len(witness))
    return len(witness)


def _string(model: CoupledModel, moves: list[str]) -> list[str]:
    """The full string of a path given by its controllable events."""
    path: list[str] = []
    state = _settled(model, (tuple(model.inst.start), (0,) * model.inst.size), path)
    for name in moves:
        state = dict(successor_events(model, state, controllable=True))[name]
        path.append(name)
        state = _settled(model, state, path)
    return path


def greedy_witness(model: CoupledModel, bound: PatternBound, limit: int = GREEDY_LIMIT, *,
                   check: Callable[[], None] | None = None) -> GreedyWitness | None:
    """A forcing string found by greedy best-first search on the settled states, or None.

    Parameters
    ----------
    model : CoupledModel
        The instance; its target must have no arm in another's safety zone.
    bound : PatternBound
        The lower bound ``h`` ordering the search (states where it is infinite are skipped).
    limit : int
        Settled states expanded at most.
    check : callable, optional
        Called at the first expansion and every :data:`CHECK_EVERY` after (a budget check may raise there).

    Returns
    -------
    GreedyWitness or None
        A string that :func:`replay` accepts, or None when the search ran out of its
        ``limit`` or of states (neither proves the start unforcible).

    Raises
    ------
    InputError
        If ``limit`` is not a positive integer.

    Examples
    --------
    >>> from supcoord.paper.run import coupled_instance
    >>> model = CoupledModel(coupled_instance(3, 8, 0))
    >>> found = greedy_witness(model, PatternBound(model))
    >>> found.length, found.witness[:4]
    (8, ('71', '71', '81', '81'))
    """
    if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
        raise InputError(f"limit must be a positive integer, got {limit!r}", value=limit, where="limit")
    size = model.inst.size
    target: State = (tuple(model.inst.target), (0,) * size)
    start_raw: State = (tuple(model.inst.start), (0,) * size)
    levels, _ = settle(model, *start_raw)
    start: State = (start_raw[0], levels)
    parent: dict[State, tuple[State, str] | None] = {start: None}
    h0 = bound.value(start[0])
    queue = [] if h0 is None else [(h0, 0, 0, start)]
    home = _homes(bound)
    expanded = tie = 0
    while queue and expanded < limit:
        hy, g, _, y = heapq.heappop(queue)
        if y == target:
            moves = []
            while parent[y] is not None:
                y, name = parent[y]
                moves.append(name)
            witness = _string(model, moves[::-1])
            return GreedyWitness(tuple(witness), replay(model, witness), expanded)
        expanded += 1
        if check is not None and expanded % CHECK_EVERY == 1:
            check()
        for name, z in successor_events(model, y, controllable=True):
            i = decode_label(name)[0] - 1  # the event's positioner: only it and its neighbours settle
            lv, d = settle(model, *z, near=i)
            nxt = (z[0], lv)
            if nxt in parent:
                continue
            table, group = home[i]  # h changes on the mover's group only
            dz = int(table[tuple(z[0][k] for k in group)])
            if dz == UNREACHABLE:
                continue
            h = hy - int(table[tuple(y[0][k] for k in group)]) + dz
            parent[nxt] = (y, name)
            tie += 1
            heapq.heappush(queue, (h, g + 1 + d, tie, nxt))
    return None


def _homes(bound: PatternBound) -> dict:
    """``{i: (table, group)}``: the pattern database of each positioner's group."""
    return {i: (table, group) for group, table in zip(bound.groups, bound.tables) for i in group}


def _moves_string(model: CoupledModel, moves: list[tuple[int, int]]) -> list[str]:
    """The full string of a path of configurations given by its steps ``(i, ±1)``: at each
    settled state the controllable event of ``P_i`` that turns it that way (``v``/``h``
    or ``w``/``l``, whichever is defined), pending events fired smallest first."""
    path: list[str] = []
    state = _settled(model, (tuple(model.inst.start), (0,) * model.inst.size), path)
    for i, s in moves:
        after = model._next[s][state[0][i]]
        name, state = next((name, z) for name, z in successor_events(model, state, controllable=True)
                           if z[0][i] == after and z[0][:i] == state[0][:i] and z[0][i + 1:] == state[0][i + 1:])
        path.append(name)
        state = _settled(model, state, path)
    return path


def position_witness(model: CoupledModel, bound: PatternBound, admits: Callable[[tuple[int, ...], int | None], bool],
                     limit: int = POSITION_LIMIT, *, check: Callable[[], None] | None = None) -> GreedyWitness | None:
    """A forcing string found by greedy best-first search on configurations, or None.

    The verdict depends on positions only (:mod:`.settled`), so this searches the graph of
    configurations (:mod:`.settled_refine`: a step of ``P_i`` allowed by every neighbour's
    pair table), ordered by the bound ``h`` of :mod:`.settled_bound`, then by the steps
    spent, skipping configurations where ``h`` is infinite or ``admits`` is false (sound
    pruning: a co-reachable over-approximation of :func:`.settled_refine.refine`).  A step
    changes one arm, so ``h`` is updated on the mover's group alone and ``admits`` is told
    which arm moved.  The
    path found is read as events (the controllable event that makes each step, pending
    events smallest first) and checked by :func:`replay`.

    Parameters
    ----------
    model : CoupledModel
        The instance; its target must have no arm in another's safety zone.
    bound : PatternBound
        The lower bound ``h`` ordering the search.
    admits : callable
        ``admits(pos, moved)``: False only where the target is unreachable from ``pos``;
        ``moved`` is None at the start, else the positioner whose step led to ``pos`` from a
        configuration admitted (:meth:`.settled_refine.Projections.admits`).
    limit : int
        Configurations expanded at most.
    check : callable, optional
        Called at the first expansion and every :data:`CHECK_EVERY` after (a budget check may raise there).

    Returns
    -------
    GreedyWitness or None
        A string that :func:`replay` accepts, or None (which proves nothing).

    Raises
    ------
    InputError
        If ``limit`` is not a positive integer.

    Examples
    --------
    >>> from supcoord.paper.run import coupled_instance
    >>> model = CoupledModel(coupled_instance(3, 8, 0))
    >>> position_witness(model, PatternBound(model), lambda pos, moved: True).length
    8
    """
    from .settled_refine import pair_tables

    if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
        raise InputError(f"limit must be a positive integer, got {limit!r}", value=limit, where="limit")
    n, size, nxt = model.inst.steps, model.inst.size, model._next
    tables = pair_tables(model)
    masks = {(i, s, p): [(j, sum(1 << q for q in range(n) if tables[(i, j, s)][p, q])) for j in model.neighbours[i]]
             for i in range(size) for s in (1, -1) for p in range(n)}  # neighbours' allowed positions, as bits
    start, target = tuple(model.inst.start), tuple(model.inst.target)
    parent: dict[tuple[int, ...], tuple[tuple[int, ...], tuple[int, int]] | None] = {start: None}
    h0 = bound.value(start)
    queue = [] if h0 is None or not admits(start, None) else [(h0, 0, start)]
    home = _homes(bound)
    expanded = 0
    while queue and expanded < limit:
        hx, g, x = heapq.heappop(queue)
        if x == target:
            moves = []
            while parent[x] is not None:
                x, step = parent[x]
                moves.append(step)
            witness = _moves_string(model, moves[::-1])
            return GreedyWitness(tuple(witness), replay(model, witness), expanded)
        expanded += 1
        if check is not None and expanded % CHECK_EVERY == 1:
            check()
        for i, s, y in _steps(x, masks, nxt):
            if y in parent:
                continue
            table, group = home[i]  # h changes on the mover's group only
            dy = int(table[tuple(y[k] for k in group)])
            if dy == UNREACHABLE or not admits(y, i):
                continue
            parent[y] = (x, (i, s))
            heapq.heappush(queue, (hx - int(table[tuple(x[k] for k in group)]) + dy, g + 1, y))
    return None


def _steps(x: tuple[int, ...], masks: dict, nxt: dict[int, list[int]]):
    """``(i, s, y)`` for every step of ``P_i`` in direction ``s`` that the neighbours'
    positions in ``x`` allow (``masks``: their allowed positions as bits), ``y`` the result."""
    for i in range(len(x)):
        for s in (1, -1):
            if all(bits >> x[j] & 1 for j, bits in masks[(i, s, x[i])]):
                yield i, s, x[:i] + (nxt[s][x[i]],) + x[i + 1:]
