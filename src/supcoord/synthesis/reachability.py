"""Reachability and coreachability: least fixpoints of partitioned images.

For a symbolic generator ``G`` with states ``Q``, a set ``W ⊆ Q`` to move inside
(``within``, default ``Q``) and a set of events ``Σ' ⊆ Σ`` (default ``Σ``):

- ``Reach_W(S) = μX. (S ∩ W) ∪ (⋃_{σ∈Σ'} Post_σ(X) ∩ W)``
  ``= {q ∈ W : ∃ s ∈ Σ'*. q = δ(p, s) for some p ∈ S ∩ W, every prefix staying in W}``;
- ``CoReach_W(T) = μX. (T ∩ W) ∪ (⋃_{σ∈Σ'} Pre_σ(X) ∩ W)``
  ``= {q ∈ W : ∃ s ∈ Σ'*. δ(q, s) ∈ T, every prefix staying in W}``.

The relations stay partitioned by event (:class:`~supcoord.des.EventRelation`): one
image is one ``AndAbstract`` over the event's written bits and a rename.  Three ways
to schedule the images (``method``), all computing the same fixpoint:

- ``"bfs"``: breadth-first frontiers, ``F := (⋃_σ Post_σ(F)) \\ X``;
- ``"chaining"``: one sweep applies the events in sequence, each to the set grown by
  the ones before it (``X := X ∪ Post_σ(X)`` for each ``σ``), until a sweep adds nothing;
- ``"saturation"`` (default): events are clustered by ``Top(σ)``, the highest BDD
  level their relation touches (for a product: the uppermost component involved);
  clusters are ordered bottom-up and the deepest dirty cluster is always fired to its
  *local* fixpoint before anything above it, as saturation does level by level.  A
  cluster that adds states dirties only the clusters that do not commute with it
  (their supports meet its write set or vice versa); a final check that no event
  adds anything makes the result exact even where ``within`` couples components.

**Local closures** (``LOCAL_CLOSURES``, used by ``"saturation"`` when ``within`` is not
given): each write group's steps are replaced by one step with the transitive closure of
the group's relation (:mod:`.closures`).  Computing the closures costs ~0.1 s, more than
a small fixpoint takes: saturation first runs ``_CLOSURE_AFTER`` images with the plain
steps and switches to the closures only if it has not ended by then, resuming from the
partial set ``X`` (``init ⊆ X ⊆ Reach(init)``, so the fixpoint is the same).


The explicit twins :func:`reachable_naive` and :func:`coreachable_naive` are the
reference the tests compare against.

References
----------
- J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
  transition relations, VLSI 1991 (partitioned images).
- G. Ciardo, G. Lüttgen, R. Siminiceanu, Saturation: an efficient iteration strategy
  for symbolic state-space generation, TACAS 2001.
- G. Ciardo, R. Marmorstein, R. Siminiceanu, Saturation unbound, TACAS 2003 (firing
  an event to its local fixpoint; transitive closure of local relations).
- J. R. Burch, E. M. Clarke, K. L. McMillan, D. L. Dill, L. J. Hwang, Symbolic model
  checking: 10^20 states and beyond, LICS 1990 (transitive closure by iterative
  squaring).
- A. Vahidi, M. Fabian, B. Lennartson, Efficient supervisory synthesis of large
  systems, Control Engineering Practice 2006 (event-partitioned workset iteration).
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, 2019, §2.5.
"""

from __future__ import annotations

from typing import Iterable

from ..bdd.context import BDD, Context, ThrottledCheck
from ..des import explicit_ops as X
from ..des.generator import Generator
from ..des.symbolic import SymbolicGenerator
from ..errors import InputError
from .closures import local_closures, work_done, write_groups
from .image_step import ImageProfile, ImageStep, event_steps

__all__ = [
    "METHODS",
    "DEFAULT_METHOD",
    "ImageProfile",
    "reachable",
    "coreachable",
    "reachable_naive",
    "coreachable_naive",
    "event_clusters",
    "trim",
    "trim_naive",
    "LOCAL_CLOSURES",
    "write_groups",
    "local_closures",
]

METHODS = ("bfs", "chaining", "saturation")
DEFAULT_METHOD = "saturation"

#: ``"saturation"`` without ``within`` fires write groups by their local closure (module
#: docstring); ``False`` restores the plain event steps (the benchmark's "old" variant)
LOCAL_CLOSURES = True
_CLOSURE_AFTER = 256  # images of plain saturation before the closures are worth computing
_CLOSURE_WORK = 2  # the closures may cost this × the work (CUDD lookups) of those images …
_CLOSURE_MIN_WORK = 10_000  # … or this many lookups (~0.01 s), whichever is more


def event_clusters(G: SymbolicGenerator, events: Iterable[str] | None = None) -> list[list[str]]:
    """The events grouped by their top BDD level, ordered bottom-up (deepest first),
    as :func:`reachable` with ``method="saturation"`` fires them."""
    return [[s.event for s in c] for c in _clusters(G.ctx, event_steps(G, events, True))]


def _clusters(ctx: Context, steps: list[ImageStep]) -> list[list[ImageStep]]:
    """Saturation's partition: events grouped by ``Top(σ)``, the highest BDD level
    (closest to the root) their relation reads or writes, deepest group first.
    (Grouping by write set instead was measured 10–25 % slower on the benchmark
    families.)"""
    groups: dict[int, list[ImageStep]] = {}
    for s in steps:
        top = min(ctx.bdd.level_of_var(b) for b in ctx.bits(sorted(s.support)))
        groups.setdefault(top, []).append(s)
    return [groups[t] for t in sorted(groups, reverse=True)]


def _merge_by_writes(ctx: Context, steps: list[ImageStep]) -> list[ImageStep]:
    """One step per write set: ``Img_{σ∨τ}(X) = Img_σ(X) ∪ Img_τ(X)`` when ``σ`` and
    ``τ`` write the same variables (``∃`` distributes over ``∨``, same rename), so a
    cluster's events cost one image per write set instead of one per event."""
    groups: dict[frozenset[str], list[ImageStep]] = {}
    for s in steps:
        groups.setdefault(s.writes, []).append(s)
    out = []
    for group in groups.values():
        if len(group) == 1:
            out.append(group[0])
            continue
        rel = ctx.false
        for s in group:
            rel |= s.relation
        first = group[0]
        support = frozenset().union(*(s.support for s in group))
        out.append(ImageStep("|".join(s.event for s in group), rel, first.qbits, first.ident, first.rbits,
                         first.forward, first.writes, support, any(s.clip for s in group)))
    return out


def _check_method(method: str) -> None:
    if method not in METHODS:
        raise InputError(f"unknown fixpoint method {method!r} (use one of {', '.join(METHODS)})", value=method)


def reachable(
    G: SymbolicGenerator,
    start: BDD | None = None,
    within: BDD | None = None,
    *,
    method: str = DEFAULT_METHOD,
    events: Iterable[str] | None = None,
) -> BDD:
    """``Reach_W(S)``: the states reachable from ``start`` (default ``q0``) moving
    inside ``within`` (default ``Q``) by the given events (default all)."""
    return _fixpoint(G, G.init if start is None else start, within, method, events, True)


def coreachable(
    G: SymbolicGenerator,
    target: BDD | None = None,
    within: BDD | None = None,
    *,
    method: str = DEFAULT_METHOD,
    events: Iterable[str] | None = None,
) -> BDD:
    """``CoReach_W(T)``: the states from which ``target`` (default ``Qm``) can be
    reached moving inside ``within`` (default ``Q``) by the given events."""
    return _fixpoint(G, G.marked if target is None else target, within, method, events, False)


def _fixpoint(G: SymbolicGenerator, seeds: BDD, within: BDD | None, method: str, events: Iterable[str] | None,
              forward: bool) -> BDD:
    """``μX. (S ∩ W) ∪ (⋃_σ Img_σ(X) ∩ W)`` with ``W = within ∩ Q``, ``Img`` = ``Post`` or ``Pre``."""
    _check_method(method)
    inside = G.invariant if within is None else within & G.invariant
    stage = "reachable" if forward else "coreachable"
    steps = event_steps(G, events, forward)
    x = seeds & inside
    if method == "saturation" and within is None and LOCAL_CLOSURES and G.ctx.backend == "cudd":
        # plain steps first (small fixpoints end here); a long one resumes from its partial
        # set with the write groups' closures: init ⊆ X ⊆ Reach(init) gives the same fixpoint
        before = work_done(G.ctx)
        x, done = _saturate(G.ctx, x, inside, steps, stage, _CLOSURE_AFTER)
        if done:
            return x
        plain = None if before is None else work_done(G.ctx) - before
        steps = local_closures(G.ctx, steps, inside, None if plain is None else max(_CLOSURE_MIN_WORK, plain * _CLOSURE_WORK))
    return _FIXPOINTS[method](G.ctx, x, inside, steps, stage)


def trim(G: SymbolicGenerator, name: str | None = None, *, method: str = DEFAULT_METHOD) -> SymbolicGenerator:
    """The trim part of ``G``: ``G`` restricted to ``Reach(q0) ∩ CoReach(Qm)`` (TCT ``trim``,
    libFAUDES ``Trim``).  The set is closed under the paths between its states (a state
    on a path from ``q0`` to an accessible and coaccessible state is both), so one
    intersection suffices; the result has no initial state when ``q0`` is blocking."""
    r = reachable(G, method=method)
    return G.restrict(r & coreachable(G, within=r, method=method), name)


# -- the three schedules -------------------------------------------------------


def _bfs(ctx: Context, init: BDD, inside: BDD, steps: list[ImageStep], stage: str) -> BDD:
    """``X_{k+1} = X_k ∪ Img(F_k)``, ``F_{k+1} = Img(F_k) \\ X_k``."""
    x, frontier, xold, k = init, init, None, 0
    while x != xold:
        xold = x
        img = ctx.false
        for s in steps:
            img |= s.image(ctx, frontier, inside)  # ⋃_σ Img_σ(F)
            ctx.check_nodes(stage, iteration=k + 1, method="bfs")
        frontier = img & ~x
        x = x | frontier
        k += 1
        ctx.check_budget(stage, iteration=k, method="bfs")
    return x


def _sweep(ctx: Context, x: BDD, inside: BDD, steps: list[ImageStep], seen: list[BDD], idx: Iterable[int],
           stage: str = "image", method: str = "chaining", iteration: int = 0) -> BDD:
    """Chaining over ``steps[i]`` for ``i`` in ``idx``: ``X := X ∪ Img_σ(X)``, skipping
    an event whose last operand ``seen_σ`` is ``X`` itself (its images are in ``X``).
    (Restricting the operand to the frontier ``X \\ seen_σ`` with Coudert's restrict
    was measured slower on the benchmark families: the sets are small and regular.)"""
    for i in idx:
        if x == seen[i]:
            continue
        seen[i] = x
        x = x | steps[i].image(ctx, x, inside)  # X ∪ Img_σ(X)
        ctx.check_nodes(stage, iteration=iteration, method=method)
    return x


def _chaining(ctx: Context, init: BDD, inside: BDD, steps: list[ImageStep], stage: str) -> BDD:
    """One sweep applies the events in turn, each to the set grown by the ones before
    it (only to states it has not seen); until a sweep adds nothing."""
    seen = [ctx.false] * len(steps)
    everything = range(len(steps))
    x, xold, k = init, None, 0
    while x != xold:
        xold = x
        x = _sweep(ctx, x, inside, steps, seen, everything, stage, "chaining", k + 1)
        k += 1
        ctx.check_budget(stage, iteration=k, method="chaining")
    return x


def _saturation(ctx: Context, init: BDD, inside: BDD, steps: list[ImageStep], stage: str) -> BDD:
    """Fire the deepest dirty cluster to its local fixpoint; re-dirty the clusters that
    do not commute with it; when none is dirty, every event whose last operand is not
    the current set dirties its cluster again (exactness where ``inside`` couples)."""
    return _saturate(ctx, init, inside, steps, stage)[0]


def _saturate(ctx: Context, init: BDD, inside: BDD, steps: list[ImageStep], stage: str,
              max_images: int | None = None) -> tuple[BDD, bool]:
    """:func:`_saturation`, stopping after about ``max_images`` images: ``(X, done)``
    with ``init ⊆ X ⊆ Reach(init)`` (so a fixpoint resumed from ``X`` is exact)."""
    merged: list[ImageStep] = []
    clusters = []
    for c in _clusters(ctx, steps):
        first = len(merged)
        merged.extend(_merge_by_writes(ctx, c))
        clusters.append(list(range(first, len(merged))))
    steps = merged
    n = len(clusters)
    writes = [frozenset().union(*(steps[i].writes for i in c)) for c in clusters]
    support = [frozenset().union(*(steps[i].support for i in c)) for c in clusters]
    # commuting clusters (disjoint supports/write sets) preserve each other's closure
    dependents = [
        [j for j in range(n) if j != k and (support[j] & writes[k] or writes[j] & support[k])] for k in range(n)
    ]
    seen = [ctx.false] * len(steps)
    x, k, images = init, 0, 0
    check = ThrottledCheck(ctx, _CHECK_EVERY)  # local fixpoints are many and cheap: throttle
    dirty = set(range(n))
    while dirty:
        if max_images is not None and images >= max_images:
            return x, False
        c = min(dirty)  # the deepest dirty cluster first
        dirty.discard(c)
        y, yold = x, None
        while y != yold:  # local fixpoint: μY. X ∪ ⋃_{σ ∈ cluster} Img_σ(Y)
            yold = y
            images += sum(1 for i in clusters[c] if seen[i] != y)  # the images this sweep takes
            y = _sweep(ctx, y, inside, steps, seen, clusters[c], stage, "saturation", k + 1)
        if y != x:
            x = y
            dirty.update(dependents[c])
        k += 1
        check(stage, iteration=k, method="saturation")
        if not dirty:
            dirty = {j for j, cl in enumerate(clusters) if any(seen[i] != x for i in cl)}
    return x, True


_CHECK_EVERY = 0.25  # seconds between budget checks inside saturation

_FIXPOINTS = {"bfs": _bfs, "chaining": _chaining, "saturation": _saturation}


# -- explicit twins --------------------------------------------------------------


def trim_naive(G: Generator, name: str | None = None) -> Generator:
    """Explicit twin of :func:`trim` (:func:`supcoord.des.explicit_ops.trim`)."""
    return X.trim(G, name)


def reachable_naive(
    G: Generator, start: Iterable[int] | None = None, within: Iterable[int] | None = None,
    events: Iterable[str] | None = None,
) -> set[int]:
    """Explicit ``Reach_W(S)`` by depth-first search (``S`` defaults to ``{q0}``;
    :func:`supcoord.des.explicit_ops.accessible_states`)."""
    return X.accessible_states(G, within, start=start, events=events)


def coreachable_naive(
    G: Generator, target: Iterable[int] | None = None, within: Iterable[int] | None = None,
    events: Iterable[str] | None = None,
) -> set[int]:
    """Explicit ``CoReach_W(T)`` by backward search (``T`` defaults to ``Qm``;
    :func:`supcoord.des.explicit_ops.coaccessible_states`)."""
    return X.coaccessible_states(G, within, target, events=events)
