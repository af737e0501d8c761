"""Backtracking forcibility as a symbolic least fixpoint: layers, rank, BFA.

For a generator ``G = (Q, Σc ⊎ Σu, δ, q0, Qm)`` write ``U(q)``/``C(q)`` for the
uncontrollable/controllable events defined at ``q``.  From a target ``T ⊆ Q``::

    W(0)   = T
    W(k+1) = W(k) ∪ Force(W(k))
    rank(q) = min {k : q ∈ W(k)}          (None where q ∉ W(∞))
    L(k)   = W(k) \\ W(k-1)                 (the layers; L(0) = T)

with two meanings of ``Force``:

- **preemptive** (the seed paper's Remark: pending uncontrollable events preempt)::

      Force(W) = {q : U(q) ≠ ∅ ∧ ∀u ∈ U(q). δ(q,u) ∈ W}
               ∪ {q : U(q) = ∅ ∧ ∃c ∈ C(q). δ(q,c) ∈ W}

- **standard** (the controller forces one event, the environment may still move first)::

      Force(W) = {q : (∃c ∈ C(q). δ(q,c) ∈ W) ∧ ∀u ∈ U(q). δ(q,u) ∈ W}

Symbolically, with the per-event partitioned relations of
:class:`~supcoord.des.symbolic.SymbolicGenerator` and ``G`` deterministic,
``∀u ∈ U(q). δ(q,u) ∈ W  ≡  ¬ ⋁_u Pre_u(Q \\ W)`` and
``∃c ∈ C(q). δ(q,c) ∈ W  ≡  ⋁_c Pre_c(W)``; the set of states with ``U(q) ≠ ∅``,
``⋁_u Pre_u(Q)``, is computed once.  Everything stays inside ``Q`` (the generator's
invariant; a supervisor is a plant product restricted to its winning set).

``W(k)`` grows monotonically inside a finite ``Q``, so the iteration stops; ``rank`` is
then the worst case over the environment's choices: from ``q ∈ L(k)`` every
uncontrollable successor the semantics lets happen lies in ``W(k-1)``, and (where the
controller acts) some controllable one does too.  :func:`bfa` keeps the part of the
layers that is forward-reachable from a source by such rank-decreasing steps (the
paper's "set of all forcible paths").  The result, :class:`~.layers.Layers`, and the
forms a state may be given in (:func:`~.layers.as_states`) live in :mod:`.layers`.

References
----------
- M. Macktoobian, W. M. Wonham, Automatic reconfiguration of untimed discrete-event
  systems, ICEEE 2017 (backtracking forcibility).
- M. Macktoobian, D. Gillet, J.-P. Kneib, Supervisory coordination of robotic fiber
  positioners in multi-object spectrographs, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (CCC).
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer 2019.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any, Iterable, Sequence

from ..bdd.context import BDD
from ..des.explicit_ops import predecessors
from ..des.generator import Generator
from ..des.symbolic import SymbolicGenerator
from .layers import SEMANTICS, Layers, LayerStats, as_single_state, as_states, check_semantics, rank_naive

__all__ = [
    "SEMANTICS",
    "Layers",
    "forcible_layers",
    "forcible_layers_naive",
    "bfa",
    "bfa_naive",
    "as_states",
    "as_single_state",
    "rank_naive",
]


@dataclass(frozen=True)
class _Cluster:
    """Events of one controllability with one write set, their relations OR-ed:
    ``Pre`` over the union is the union of the ``Pre`` (same frame, same primed bits).
    ``ident`` is ``I_W = ∧_{b ∈ W} (b ↔ b')``: ``X[x_W := x'_W] = ∃x_W. X ∧ I_W``, one
    ``AndAbstract`` over the adjacent twins instead of ``dd``'s ``let``, whose cost
    grows with the number of declared variables."""

    controllable: bool
    writes: tuple[str, ...]
    relation: BDD
    primed_bits: tuple[str, ...]
    bits: tuple[str, ...] = ()
    ident: BDD = None


def clusters(G: SymbolicGenerator) -> list[_Cluster]:
    """``G``'s events grouped by (controllable, write set), in first-seen order."""
    ctx = G.ctx
    groups: dict[tuple[bool, tuple[str, ...]], BDD] = {}
    for r in G.events.values():
        key = (r.event.controllable, tuple(r.writes))
        groups[key] = groups.get(key, ctx.false) | r.relation
    idents: dict[tuple[str, ...], BDD] = {}
    out = []
    for (c, w), rel in groups.items():
        if w not in idents:
            idents[w] = ctx.identity(w)
        out.append(_Cluster(c, w, rel, tuple(ctx.bits(w, primed=True)), tuple(ctx.bits(w)), idents[w]))
    return out


def uncontrollable_enabled(G: SymbolicGenerator) -> BDD:
    """``{q ∈ Q : U(q) ≠ ∅} = ⋁_u Pre_u(Q)``."""
    out = G.ctx.false
    for en in G.enabled_sets(G.uncontrollable).values():
        out |= en
    return out


def force(G: SymbolicGenerator, W: BDD, Q: BDD, env_states: BDD, semantics: str,
          groups: Sequence[_Cluster] | None = None,
          primed_inv: dict[tuple[str, ...], BDD] | None = None) -> BDD:
    """``Force(W)`` inside ``Q``: the states from which one step can be forced into ``W``.

    ``Pre_σ(X) = ∃x'_W. R_σ ∧ X[x_W := x'_W]``; each write set is primed once per call
    and serves both ``Pre_c(W)`` and ``Pre_u(Q_G \\ W)``, since
    ``(Q_G \\ W)[x_W := x'_W] = Q_G[x_W := x'_W] ∧ ¬W[x_W := x'_W]``.

    Parameters
    ----------
    G : SymbolicGenerator
        The generator, deterministic.
    W : BDD
        The states already won (over ``G``'s unprimed variables).
    Q : BDD
        The states that may be won (within ``G``'s invariant).
    env_states : BDD
        ``{q : U(q) ≠ ∅}``, the states with an uncontrollable event
        (:func:`uncontrollable_enabled`).
    semantics : {"preemptive", "standard"}
        ``"preemptive"``: ``{q : U(q) ≠ ∅ ∧ ∀u ∈ U(q). δ(q,u) ∈ W} ∪ {q : U(q) = ∅ ∧
        ∃c ∈ C(q). δ(q,c) ∈ W}``; ``"standard"``: ``{q : (∃c ∈ C(q). δ(q,c) ∈ W) ∧
        ∀u ∈ U(q). δ(q,u) ∈ W}``.
    groups : sequence of clusters, optional
        ``G``'s relations grouped by controllability and write set (:func:`clusters`),
        when the caller keeps them across calls.
    primed_inv : dict, optional
        A cache, write set -> ``Q_G[x_W := x'_W]``, kept by the caller across calls.

    Returns
    -------
    BDD
        ``Force(W) ∩ Q`` (it may include states of ``W``).

    See Also
    --------
    forcible_layers : the fixpoint ``W(k+1) = W(k) ∪ Force(W(k))``.

    References
    ----------
    .. [1] M. Macktoobian, W. M. Wonham, "Automatic reconfiguration of untimed
       discrete-event systems", ICEEE 2017 (backtracking forcibility).
    .. [2] M. Macktoobian, D. Gillet, J.-P. Kneib, "Supervisory coordination of robotic
       fiber positioners in multi-object spectrographs", IFAC-PapersOnLine 52(3), 2019,
       doi:10.1016/j.ifacol.2019.06.011 (the preemptive semantics: its Remark).

    Examples
    --------
    ``0 -a-> 1 -u-> 2`` with ``a`` controllable, ``u`` not, and ``W = {2}``: state 1
    has only ``u``, which leads into ``W``, so it is forced under the preemptive
    semantics; under the standard one no controllable event leaves it.

    >>> from supcoord.bdd import Context
    >>> from supcoord.des.generator import Event, Generator
    >>> from supcoord.des.symbolic import from_explicit
    >>> g = Generator(3, [Event("a", True), Event("u", False)], [(0, "a", 1), (1, "u", 2)], 0, [2], name="g")
    >>> S = from_explicit(Context(), g)
    >>> env = uncontrollable_enabled(S)
    >>> F = force(S, S.marked, S.invariant, env, "preemptive")
    >>> [q for q in range(3) if S.ctx.eq("g", q) & F != S.ctx.false]
    [1]
    >>> force(S, S.marked, S.invariant, env, "standard") == S.ctx.false
    True
    """
    ctx = G.ctx
    inv = G.invariant
    w = W & inv
    primed_inv = {} if primed_inv is None else primed_inv
    primed: dict[tuple[str, ...], tuple[BDD, BDD]] = {}
    bad_u = ctx.false
    some_c = ctx.false
    for cl in clusters(G) if groups is None else groups:
        t = primed.get(cl.writes)
        if t is None:
            inv_p = primed_inv.get(cl.writes)
            if inv_p is None:
                inv_p = primed_inv[cl.writes] = ctx.and_exist(inv, cl.ident, cl.bits)  # Q_G[x_W := x'_W]
            w_p = ctx.and_exist(w, cl.ident, cl.bits)  # W[x_W := x'_W]
            t = primed[cl.writes] = (w_p, inv_p & ~w_p)
        w_p, not_w_p = t
        if cl.controllable:
            some_c |= ctx.and_exist(cl.relation, w_p, cl.primed_bits)  # ∃c ∈ C(q). δ(q,c) ∈ W
        else:
            bad_u |= ctx.and_exist(cl.relation, not_w_p, cl.primed_bits)  # ∃u ∈ U(q). δ(q,u) ∉ W
    all_u_ok = Q & ~bad_u  # ∀u ∈ U(q). δ(q,u) ∈ W
    if semantics == "preemptive":
        return (env_states & all_u_ok) | (Q & ~env_states & some_c)
    return Q & some_c & all_u_ok


def forcible_layers(
    G: SymbolicGenerator,
    target: Any,
    *,
    semantics: str = "preemptive",
    within: BDD | None = None,
    stop_at: Any = None,
) -> Layers:
    """The layers ``L(0), L(1), …`` of ``W(k+1) = W(k) ∪ Force(W(k))``, ``W(0) = T``.

    ``target`` is a BDD (or a state, see :func:`as_states`); ``within`` restricts the
    states that may be won (successors outside it count as losing); ``stop_at`` ends
    the iteration as soon as ``stop_at ⊆ W(k)`` (e.g. the source state), leaving
    ``complete = False``.  Calls ``ctx.check_budget("force", iteration=k, …)`` once per
    layer.  (Computing each layer from the last one alone, ``Q ∩ Pre(L(k)) \\ W(k)``
    being the only candidates, was measured 1.1–6× slower on supervisors: the layers'
    BDDs are far larger than the ``W(k)``'s.)
    """
    check_semantics(semantics)
    ctx = G.ctx
    started = time.perf_counter()
    Q = G.invariant if within is None else G.invariant & within
    env_states = uncontrollable_enabled(G)
    groups = clusters(G)
    if semantics == "preemptive":  # C(q) counts only where U(q) = ∅, U(q) only where U(q) ≠ ∅:
        # each relation restricted to the sources where it counts, so every image is
        # smaller (the coupled paper model's layers 2-2.7x faster, benchmarks/results/coupled_sets.md)
        groups = [replace(g, relation=g.relation & Q & (~env_states if g.controllable else env_states))
                  for g in groups]
    primed_inv: dict[tuple[str, ...], BDD] = {}
    stop = None if stop_at is None else as_states(G, stop_at)
    w = as_states(G, target) & Q
    layers = [w]
    complete = True
    k = 0
    xold = None
    while w != xold:
        ctx.check_budget("force", iteration=k, layer_nodes=ctx.node_count(layers[-1]))
        if stop is not None and (stop & ~w) == ctx.false:
            complete = False
            break
        xold = w
        w = xold | force(G, xold, Q, env_states, semantics, groups, primed_inv)  # W(k+1) = W(k) ∪ Force(W(k))
        if w != xold:
            layers.append(w & ~xold)  # L(k+1) = W(k+1) \ W(k)
            k += 1
    stats: LayerStats = {
        "iterations": k,
        "seconds": time.perf_counter() - started,
        "bdd_nodes": ctx.node_count(*layers),
        "peak_nodes": ctx.peak_nodes(),
    }
    return Layers(G, layers, w, semantics, env_states, complete, stats)


# -- the set of all forcible paths -------------------------------------------------


def allowed_successors(G: SymbolicGenerator, lay: Layers, states: BDD, below: BDD) -> BDD:
    """Successors of ``states`` (all in one layer ``L(k)``) along the steps the
    semantics allows into ``below = W(k-1)``: every uncontrollable event where the
    environment may move, controllable events into ``below`` where the controller acts."""
    env = states & lay.env_states
    ctrl = states & lay.controller_states()
    out = G.ctx.false
    if lay.semantics == "standard":
        env = states
    for u in G.uncontrollable:
        out |= G.post(env, u)  # all lie in W(k-1) by construction of L(k)
    for c in G.controllable:
        out |= G.post(ctrl, c) & below  # a rank-decreasing forced step
    return out


def bfa(G: SymbolicGenerator, source: Any, target: Any, semantics: str = "preemptive") -> Layers:
    """``BFA(G, source, target)``: the layers of the target restricted to the states
    forward-reachable from ``source`` along rank-decreasing allowed steps.

    The result's ``layers[k]`` is ``L(k) ∩ R`` for ``k ≤ rank(source)``, where ``R`` is
    that reachable set; it is empty (``layers == []``) when ``source`` is not forcible.
    """
    check_semantics(semantics)
    src = as_states(G, source)
    full = forcible_layers(G, target, semantics=semantics, stop_at=src)
    top = full.rank(src)
    false = G.ctx.false
    if top is None:
        return Layers(G, [], false, semantics, full.env_states, full.complete, LayerStats(full.stats))
    prefixes = [false]
    for layer in full.layers[:top]:
        prefixes.append(prefixes[-1] | layer)  # prefixes[k] = W(k-1)
    reach = src
    for k in range(top, 0, -1):
        here = reach & full.layers[k]
        reach |= allowed_successors(G, full, here, prefixes[k])
    layers = [layer & reach for layer in full.layers[: top + 1]]
    stats = LayerStats(full.stats, dag_nodes=G.ctx.node_count(*layers))
    winning = false
    for layer in layers:
        winning |= layer
    return Layers(G, layers, winning, semantics, full.env_states, True, stats)


# -- the explicit twin -------------------------------------------------------------


def forced_naive(g: Generator, q: int, W: set[int], semantics: str) -> bool:
    """``q ∈ Force(W)`` read straight from the definition."""
    out = g.enabled(q)
    U = [d for e, d in out.items() if not g.events[e].controllable]
    C = [d for e, d in out.items() if g.events[e].controllable]
    if semantics == "preemptive":
        return all(d in W for d in U) if U else any(d in W for d in C)
    return any(d in W for d in C) and all(d in W for d in U)


def forcible_layers_naive(
    g: Generator, target: Iterable[int], semantics: str = "preemptive", within: Iterable[int] | None = None
) -> list[set[int]]:
    """Explicit layers ``[L(0), L(1), …]``: backward breadth-first over predecessors.

    A state entering ``W(k+1)`` has a successor in ``L(k)`` (otherwise it would already
    satisfy ``Force(W(k-1))``), so only predecessors of the last layer are candidates.
    ``within`` (default: all states) bounds the states that may be won.
    """
    check_semantics(semantics)
    allowed = set(range(g.n_states)) if within is None else set(within)
    preds = predecessors(g)
    W = {q for q in target if q in allowed}
    layers = [set(W)]
    while True:
        candidates = {p for q in layers[-1] for p in preds.get(q, ()) if p not in W and p in allowed}
        new = {q for q in candidates if forced_naive(g, q, W, semantics)}
        if not new:
            return layers
        W |= new
        layers.append(new)


def bfa_naive(g: Generator, source: int, target: Iterable[int], semantics: str = "preemptive") -> list[set[int]]:
    """Explicit twin of :func:`bfa`: the layers ``L(0) … L(rank(source))`` restricted to
    the states reachable from ``source`` by allowed rank-decreasing steps (``[]`` when
    ``source`` is not forcible)."""
    full = forcible_layers_naive(g, target, semantics)
    top = rank_naive(full, source)
    if top is None:
        return []
    seen, stack = {source}, [source]
    while stack:
        q = stack.pop()
        k = rank_naive(full, q)
        if k == 0:
            continue
        out = g.enabled(q)
        env = semantics == "preemptive" and any(not g.events[e].controllable for e in out)
        for e, d in out.items():
            if g.events[e].controllable:
                j = rank_naive(full, d)
                ok = not env and j is not None and j < k  # a forced rank-decreasing step
            else:
                ok = env or semantics == "standard"  # the environment may move (into W(k-1))
            if ok and d not in seen:
                seen.add(d)
                stack.append(d)
    return [layer & seen for layer in full[: top + 1]]
