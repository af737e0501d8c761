"""Variable ordering: in which order to declare the components' variables.

:meth:`Context.add_variable` lays variables out in declaration order, so choosing a
static order means choosing the order in which the components (plants and
specifications, each one finite-domain variable) are declared.  The heuristics work
on the *interaction hypergraph*: one node per component, one hyperedge per event
joining the components whose alphabets contain it.  Components that share events
should sit close together: a relation ``R_σ`` then spans few levels and the sets
stay narrow.

- ``"given"``: the order given;
- ``"interleave"``: each plant followed by the specifications whose events the
  plants so far cover (a buffer right after the machines it couples);
- ``"rcm"``: reverse Cuthill–McKee on the interaction graph (components adjacent
  when they share an event): breadth-first from a pseudo-peripheral component,
  neighbours by increasing degree, the whole order reversed — small bandwidth;
- ``"force"``: the FORCE heuristic: repeatedly move every component to the mean of
  the centres of gravity of its events, and sort — small total span.

Dynamic reordering (CUDD's sifting) is the fallback when no static order fits:
:func:`set_reordering` switches it on for the manager, :func:`reorder_now` sifts once.

The functions take the components as alphabets (iterables of event names), except
:func:`cuthill_mckee`, which takes a plain graph (adjacency lists) and is also the
reverse Cuthill–McKee of :mod:`supcoord.planning.graph_order`; this bottom layer depends
on nothing above it.

References
----------
- E. Cuthill, J. McKee, Reducing the bandwidth of sparse symmetric matrices, 1969;
  A. George, Computer implementation of the finite element method, 1971 (reverse).
- F. A. Aloul, I. L. Markov, K. A. Sakallah, FORCE: a fast and easy-to-implement
  variable-ordering heuristic, GLSVLSI 2003.
- R. Rudell, Dynamic variable ordering for ordered binary decision diagrams, ICCAD 1993.
"""

from __future__ import annotations

from typing import Iterable, Sequence

from ..errors import InputError

__all__ = [
    "ORDERINGS",
    "interaction_graph",
    "order_components",
    "rcm_order",
    "cuthill_mckee",
    "bandwidth",
    "force_order",
    "interleaved_order",
    "span",
    "set_reordering",
    "reorder_now",
]

ORDERINGS = ("given", "interleave", "rcm", "force")


def _alphabets(components: Sequence[Iterable[str]]) -> list[frozenset[str]]:
    return [frozenset(a) for a in components]


def interaction_graph(components: Sequence[Iterable[str]]) -> list[set[int]]:
    """``adj[i] = {j ≠ i : Σ_i ∩ Σ_j ≠ ∅}``.

    >>> interaction_graph([{"a"}, {"a", "b"}, {"b"}, {"c"}])
    [{1}, {0, 2}, {1}, set()]
    """
    alph = _alphabets(components)
    users: dict[str, list[int]] = {}
    for i, a in enumerate(alph):
        for e in a:
            users.setdefault(e, []).append(i)
    adj: list[set[int]] = [set() for _ in alph]
    for comps in users.values():
        for i in comps:
            adj[i].update(j for j in comps if j != i)
    return adj


def _levels(adj: Sequence[Sequence[int]], root: int) -> list[list[int]]:
    """The breadth-first level structure of ``root``'s connected part."""
    levels, seen = [[root]], {root}
    while True:
        nxt = []
        for i in levels[-1]:
            for j in adj[i]:
                if j not in seen:
                    seen.add(j)
                    nxt.append(j)
        if not nxt:
            return levels
        levels.append(nxt)


def cuthill_mckee(adj: Sequence[Iterable[int]]) -> list[list[int]]:
    """The Cuthill–McKee order of each connected part of the graph ``adj`` (``adj[i]``:
    the neighbours of node ``i``), the parts in order of their least node: breadth-first
    from a pseudo-peripheral node, neighbours by increasing ``(degree, index)``.

    The start: the node of least ``(degree, index)``, then (George–Liu) the least node of
    the last level of its level structure, at most three times (rather than while the
    structure deepens: 10–20 % fewer BDD nodes on the conflict-graph windows of 14–43
    positioners where the two rules differ; the same order on every DES family and
    classic model here).  Ties are broken by index, so the order is the same on every
    machine.  Not :func:`scipy.sparse.csgraph.reverse_cuthill_mckee`: it starts at a
    least-degree node picked by numpy's unstable ``argsort``, which depends on the CPU's
    SIMD instructions (measured: another start on the same hex conflict graph without
    AVX2), so BDD sizes, window node caps and plans would differ between machines; nor
    were its orders better (another of the symmetric hexagon corners as start: fewer
    nodes on 15 of 21 windows of 7–19 positioners, about 40 % more on windows of 36–61).

    >>> cuthill_mckee([[2], [3], [0, 3], [2, 1], []])  # a chain 0-2-3-1 and a lone node
    [[1, 3, 2, 0], [4]]
    """
    adj = [list(a) for a in adj]

    def key(j: int) -> tuple[int, int]:
        return len(adj[j]), j

    placed = [False] * len(adj)
    parts = []
    for first in range(len(adj)):
        if placed[first]:
            continue
        start = min((i for level in _levels(adj, first) for i in level), key=key)
        for _ in range(3):  # to the far end of a breadth-first search
            candidate = min(_levels(adj, start)[-1], key=key)
            if candidate == start:
                break
            start = candidate
        order = [start]
        placed[start] = True
        for i in order:  # breadth-first: the list grows while it is read
            for j in sorted(adj[i], key=key):
                if not placed[j]:
                    placed[j] = True
                    order.append(j)
        parts.append(order)
    return parts


def bandwidth(adj: Sequence[Iterable[int]], order: Sequence[int]) -> int:
    """``max |π(i) − π(j)|`` over the edges ``i — j`` of ``adj`` for the order ``π``
    (``order[k]`` is the node at position ``k``): how far apart an order puts two
    neighbours, the quantity Cuthill–McKee keeps small (0 for a graph without edges).

    >>> bandwidth([[1, 2], [0], [0]], [1, 0, 2]), bandwidth([[1, 2], [0], [0]], [1, 2, 0])
    (1, 2)
    """
    pos = {node: k for k, node in enumerate(order)}
    if len(pos) != len(adj) or set(pos) != set(range(len(adj))):
        raise InputError(f"an order of the {len(adj)} nodes needs each exactly once, got {list(order)!r}",
                         value=list(order))
    return max((abs(pos[i] - pos[j]) for i, nbrs in enumerate(adj) for j in nbrs), default=0)


def rcm_order(components: Sequence[Iterable[str]]) -> list[int]:
    """Reverse Cuthill–McKee order of the components: the :func:`cuthill_mckee` order
    of the interaction graph, reversed as a whole.

    >>> rcm_order([{"a"}, {"c"}, {"a", "b"}, {"b", "c"}])  # a chain 0-2-3-1
    [0, 2, 3, 1]
    """
    return [i for part in cuthill_mckee(interaction_graph(components)) for i in part][::-1]


def span(components: Sequence[Iterable[str]], order: Sequence[int]) -> int:
    """Total span ``Σ_σ (max pos − min pos)`` of the events over a component order:
    the quantity FORCE minimizes (smaller is usually a smaller BDD).

    >>> span([{"a"}, {"b"}, {"a", "b"}], [0, 1, 2]), span([{"a"}, {"b"}, {"a", "b"}], [0, 2, 1])
    (3, 2)
    """
    pos = {c: i for i, c in enumerate(order)}
    extent: dict[str, tuple[int, int]] = {}
    for c, a in enumerate(_alphabets(components)):
        for e in a:
            lo, hi = extent.get(e, (pos[c], pos[c]))
            extent[e] = (min(lo, pos[c]), max(hi, pos[c]))
    return sum(hi - lo for lo, hi in extent.values())


def force_order(components: Sequence[Iterable[str]], start: Sequence[int] | None = None, rounds: int = 30) -> list[int]:
    """The FORCE heuristic from ``start`` (default: reverse Cuthill–McKee); the best
    order seen by :func:`span` is returned.

    >>> force_order([{"a"}, {"b"}, {"a", "b"}])  # the shared component in the middle
    [0, 2, 1]
    """
    alph = _alphabets(components)
    order = list(start) if start is not None else rcm_order(components)
    best, best_span = list(order), span(alph, order)
    events = sorted({e for a in alph for e in a})
    for _ in range(rounds):
        pos = {c: i for i, c in enumerate(order)}
        cog = {}
        for e in events:
            users = [pos[c] for c, a in enumerate(alph) if e in a]
            cog[e] = sum(users) / len(users)
        target = {c: (sum(cog[e] for e in alph[c]) / len(alph[c]) if alph[c] else pos[c]) for c in order}
        new = sorted(order, key=lambda c: (target[c], pos[c]))
        if new == order:
            break
        order = new
        s = span(alph, order)
        if s < best_span:
            best, best_span = list(order), s
    return best


def interleaved_order(components: Sequence[Iterable[str]], is_spec: Sequence[bool]) -> list[int]:
    """Each plant, then every specification whose events the plants so far cover;
    specifications never covered go last.

    >>> interleaved_order([{"a"}, {"b"}, {"a"}, {"b"}], [False, False, True, True])
    [0, 2, 1, 3]
    """
    alph = _alphabets(components)
    if len(is_spec) != len(alph):
        raise InputError(f"{len(is_spec)} kinds for {len(alph)} components", value=len(is_spec))
    order: list[int] = []
    covered: set[str] = set()
    pending = [j for j, s in enumerate(is_spec) if s]
    for i, s in enumerate(is_spec):
        if s:
            continue
        order.append(i)
        covered |= alph[i]
        ready = [j for j in pending if alph[j] <= covered]
        order += ready
        pending = [j for j in pending if j not in ready]
    return order + pending


def order_components(
    components: Sequence[Iterable[str]], method: str = "interleave", is_spec: Sequence[bool] | None = None
) -> list[int]:
    """The declaration order of the components by ``method`` (one of :data:`ORDERINGS`).

    >>> order_components([{"a"}, {"b"}, {"a"}], "given")
    [0, 1, 2]
    """
    comps = list(components)
    if method == "given":
        return list(range(len(comps)))
    if method == "interleave":
        return interleaved_order(comps, is_spec if is_spec is not None else [False] * len(comps))
    if method == "rcm":
        return rcm_order(comps)
    if method == "force":
        return force_order(comps)
    raise InputError(f"unknown variable ordering {method!r} (use one of {', '.join(ORDERINGS)})", value=method)


def set_reordering(ctx, enabled: bool = True) -> None:
    """Switch CUDD's dynamic reordering (sifting) on or off for ``ctx``'s manager."""
    ctx.bdd.configure(reordering=bool(enabled))


def reorder_now(ctx) -> tuple[int, int]:
    """Sift once now; returns the live node counts ``(before, after)``."""
    before = ctx.live_nodes()
    ctx.bdd.reorder()
    return before, ctx.live_nodes()
