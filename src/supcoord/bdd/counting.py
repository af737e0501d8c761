"""Exact model counting by a walk of the BDD in Python (the reference and fallback of
:meth:`supcoord.bdd.Context.count`; CUDD's own arbitrary-precision count is in
:mod:`supcoord.bdd.cudd_count`).

With complemented edges, ``low``/``high`` are the children of the *regular* node and
``count(¬f) = 2^k − count(f)`` over the ``k`` care bits at or below ``f``; each node's
count over the care bits below it is memoised, so the walk is linear in the DAG.

References
----------
- R. E. Bryant, Graph-based algorithms for Boolean function manipulation, IEEE TC 1986.
"""

from __future__ import annotations

from typing import Any, Sequence

from .backend import BDD

__all__ = ["exact_count"]


def exact_count(bdd: Any, u: BDD, care: Sequence[str]) -> int:
    """Number of satisfying assignments of ``u`` over the bits ``care`` (Python ints).

    Walks the DAG once (iteratively: orders can be tens of thousands of levels deep).
    With complemented edges, ``low``/``high`` are the children of the *regular* node,
    and ``count(¬f) = 2^k − count(f)`` over the ``k`` care bits at or below ``f``.
    """
    levels = sorted(bdd.level_of_var(b) for b in care)
    n = len(levels)
    position = {lvl: i for i, lvl in enumerate(levels)}

    def pos(f: BDD) -> int:
        return n if f.var is None else position[f.level]

    def regular_key(f: BDD) -> int:
        return int(~f) if f.negated else int(f)

    memo: dict[int, int] = {}  # regular node -> count over care bits at/below it

    def value(f: BDD) -> int:
        # count of f (with its own negation) over care bits at/below pos(f)
        if f.var is None:
            return 1 if f == bdd.true else 0
        c = memo[regular_key(f)]
        return (1 << (n - pos(f))) - c if f.negated else c

    stack = [(u, False)]
    while stack:
        f, expanded = stack.pop()
        if f.var is None:
            continue
        key = regular_key(f)
        if key in memo:
            continue
        lo, hi = f.low, f.high
        if not expanded:
            stack.append((f, True))
            for child in (lo, hi):
                if child.var is not None and regular_key(child) not in memo:
                    stack.append((child, False))
            continue
        p = pos(f)
        memo[key] = value(lo) * (1 << (pos(lo) - p - 1)) + value(hi) * (1 << (pos(hi) - p - 1))
    return value(u) * (1 << pos(u))
