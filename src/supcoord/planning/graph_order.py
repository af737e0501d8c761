"""Parts and orders of the conflict graph: which positioners interact, and where their variables go.

A BDD over pairwise-coupled variables stays small when coupled variables sit close in
the order (:mod:`supcoord.bdd.ordering`).  On the conflict graph
(:func:`.guards.conflict_graph`, induced on a window's members):

- :func:`conflict_components`: its connected components (independent subproblems);
- :func:`rcm_order`: reverse Cuthill–McKee (small bandwidth), the default;
- :func:`cutwidth_order`: least (weighted) cutwidth, exact on small windows;
- :func:`hex_order`: the layout order.

References
----------
- E. Cuthill, J. McKee, Reducing the bandwidth of sparse symmetric matrices, 1969
  (reverse Cuthill–McKee: A. George, 1971).
"""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

from ..bdd.ordering import cuthill_mckee
from ..problems.problem import Problem
from .guards import conflict_graph, coupling_bits

__all__ = ["conflict_components", "rcm_order", "cutwidth_order", "hex_order"]


def _induced(problem: Problem, members: Iterable[int] | None) -> tuple[list[int], list[list[int]]]:
    """``(nodes, adj)``: the members, sorted (default: every positioner), and the conflict
    graph induced on them as adjacency lists of indices into ``nodes``."""
    graph = conflict_graph(problem)
    nodes = list(range(problem.n)) if members is None else sorted(set(int(p) for p in members))
    index = {p: i for i, p in enumerate(nodes)}
    return nodes, [[index[q] for _, q, _ in graph[p] if q in index] for p in nodes]


def conflict_components(problem: Problem) -> list[list[int]]:
    """Connected components of the conflict graph, each sorted, in order of their least member
    (:func:`scipy.sparse.csgraph.connected_components`)."""
    nodes, adj = _induced(problem, None)
    rows = [i for i, a in enumerate(adj) for _ in a]
    cols = [j for a in adj for j in a]
    matrix = csr_array((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(len(nodes), len(nodes)))
    _, labels = connected_components(matrix, directed=False)
    parts: dict[int, list[int]] = {}
    for p, label in enumerate(labels.tolist()):
        parts.setdefault(label, []).append(p)
    return sorted(parts.values())  # disjoint sorted lists: by least member


def rcm_order(problem: Problem, members: Iterable[int] | None = None) -> list[int]:
    """Reverse Cuthill–McKee order of the conflict graph (induced on ``members`` if
    given): each connected part in the :func:`~supcoord.bdd.ordering.cuthill_mckee` order
    reversed, the parts in order of their least member.  Conflicting positioners end up
    close in the variable order (small bandwidth)."""
    nodes, adj = _induced(problem, members)
    return [nodes[i] for part in cuthill_mckee(adj) for i in reversed(part)]


def cutwidth_order(problem: Problem, members: Iterable[int], exact_up_to: int = 10,
                   weighted: bool = True) -> list[int]:
    """An order of ``members`` of least *weighted cutwidth* on the induced conflict graph:
    minimise ``(max_i cut_i, Σ_i cut_i)`` with ``cut_i`` the summed weights of the conflict
    pairs with one end among the first ``i`` members and the other after them.

    A BDD over pairwise-coupled variables has at most ``∏`` (subfunctions each pair leaves
    across the cut) nodes per level, so the cut is the quantity to keep small (bandwidth,
    what reverse Cuthill–McKee minimises, only bounds it).  The weight of a pair is
    ``log2`` of that number (:func:`.guards.coupling_bits`); ``weighted=False`` counts pairs.
    Exact up to ``exact_up_to`` members (dynamic programming over subsets: the least max
    cut, then the least sum among the orders within it), :func:`rcm_order` beyond.

    Measured on a 6-robot alpha-beta window (a strip of triangles): 2 s for 13 forward
    layers in the least-cutwidth order, 7 to 28 s in other orders of the same members.
    On a 5-robot window of SDSS-V robots at 36 × 19 positions whose members all
    conflict, 14 forward layers took 0.33–1.00 s over its 120 orders; the least weighted
    cutwidth ranked 10th (0.38 s), the unweighted one 59th; on the whole 127-robot run the
    difference was within noise (``benchmarks/bench_window_order.py``)."""
    nodes = sorted(set(int(p) for p in members))
    n = len(nodes)
    if n > exact_up_to:
        return rcm_order(problem, nodes)
    index = {p: i for i, p in enumerate(nodes)}
    weight = np.zeros((n, n))
    for p in nodes:
        for k, q, _ in conflict_graph(problem)[p]:
            if q in index:
                weight[index[p], index[q]] = coupling_bits(problem, k) if weighted else 1.0
    full = (1 << n) - 1
    inside = (np.arange(full + 1)[:, None] >> np.arange(n)) & 1  # [set, member]
    cut = np.round(((inside @ weight) * (1 - inside)).sum(axis=1), 9).tolist()  # weight leaving each set
    # least max cut per set of first members (the bottleneck is monotone: exact by DP) ...
    width = [0.0] * (full + 1)
    for m in range(1, full + 1):
        width[m] = max(cut[m], min(width[m & ~(1 << i)] for i in range(n) if m >> i & 1))
    bound = width[full]
    # ... then the least sum of cuts among the orders whose every cut is within it
    total: list[float] = [math.inf] * (full + 1)
    last = [-1] * (full + 1)
    total[0] = 0.0
    for m in range(1, full + 1):
        if cut[m] > bound:
            continue
        for i in range(n):
            if m >> i & 1 and total[m & ~(1 << i)] + cut[m] < total[m]:
                total[m], last[m] = total[m & ~(1 << i)] + cut[m], i
    order = []
    m = full
    while m:
        order.append(nodes[last[m]])
        m &= ~(1 << last[m])
    return order[::-1]


def hex_order(problem: Problem) -> list[int]:
    """The layout order (hex: centre, then ring by ring): the plain default."""
    return list(range(problem.n))
