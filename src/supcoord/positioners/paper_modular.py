"""Exact decomposition of the literal model: supcon per positioner, CCC certificate.

In the literal reading the positioners share no events and no variables: the plant
is ``G = G_1 || … || G_N`` and the specification ``E = E_1 || … || E_N`` with
``E_i = allevents(G_i) || S_i`` over ``Σ_i`` (pairwise disjoint), so the product
``P = G × E`` is ``P_1 × … × P_N``.  Two facts make ``N`` small computations replace one
big one (both proven here and tested against the generic algorithms in
``tests/test_paper.py``):

**Theorem 1 (supcon).** Let ``Z_i`` be the state set of ``supcon(G_i, E_i)`` (the
greatest ``Z ⊆ Reach(P_i) \\ B0_i`` that is coreachable to ``Qm_i`` inside ``Z`` and
closed under uncontrollable events of ``G_i``, then restricted to what is reachable).
If every ``Z_i`` is nonempty, ``supcon(G, E)`` is ``P`` restricted to ``Z_1 × … × Z_N``;
otherwise it is empty.

*Proof.* ``Reach(P) = ∏ Reach(P_i)``, ``Qm = ∏ Qm_i`` and ``B0 = ⋃_i {x : x_i ∈ B0_i}``
because an event moves one component only.  (⊇) ``∏ Z_i`` avoids ``B0``, is closed under
uncontrollable events (each moves one ``x_i`` inside ``Z_i``) and is coreachable inside
itself (reach ``Qm_1`` moving component 1 only, then component 2, …), so it lies in
the greatest such set ``Z``.  (⊆) Let ``Y_i = {x_i : x ∈ Z}``.  ``Y_i`` avoids ``B0_i``; an
uncontrollable ``u ∈ Σ_i`` defined at ``x_i`` is defined at ``x`` and leads to ``x' ∈ Z``
with ``x'_i = δ_i(x_i, u)``, so ``Y_i`` is closed; projecting a path inside ``Z`` to
``Qm`` onto ``Σ_i`` gives one inside ``Y_i`` to ``Qm_i``.  Hence ``Y_i ⊆ Z_i`` and
``Z ⊆ ∏ Y_i ⊆ ∏ Z_i``.  Reachability inside a product from ``(q0_1, …, q0_N)`` is the
product of the components' reachability.  ∎

So ``|V| = ∏ |V_i|``, ``|δ_V| = Σ_i |δ_{V_i}| · ∏_{j≠i} |V_j|``, ``|Qm_V| = ∏ |Qm_{V_i}|``.

**Theorem 2 (forcibility, necessary condition).** For ``V = ∏ V_i`` (disjoint
alphabets) and target ``T = ∏ T_i``, under either semantics of
:mod:`supcoord.synthesis.forcibility`, ``W(V) ⊆ ∏ W(V_i)``.  So if some ``q0_i`` is not
forcible in ``V_i``, ``q0`` is not forcible in ``V`` (the converse fails in general:
design.md §3's counterexample, and the reason this is only a certificate).

*Proof.* By induction on ``rank(x)``.  ``rank 0``: ``x ∈ T``, so ``x_i ∈ T_i``.  ``rank r``:
if the environment acts (preemptive: ``U(x) ≠ ∅``; standard: always, for the
uncontrollable part) every ``u ∈ U(x)`` leads into ``W(r−1)``; those of ``Σ_i`` change
only ``x_i`` (induction: the successors' ``i``-parts are in ``W(V_i)``), the others leave
``x_i`` unchanged (induction: ``x_i ∈ W(V_i)``).  Where a controllable ``c`` is forced,
``c ∈ Σ_i`` gives a successor whose ``i``-part is in ``W(V_i)`` and ``c ∉ Σ_i`` leaves
``x_i`` as it is.  In each case ``x_i`` satisfies ``Force_i`` (note ``U(x) = ∅`` implies
``U_i(x_i) = ∅``) or is already in ``W(V_i)``.  ∎

References
----------
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, 2019, §4
  (modular supervision; shuffle products).
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019 (the seed paper).
"""

from __future__ import annotations

import time
from math import prod

from ..des.symbolic import SymbolicGenerator
from ..symbolic.context import Context
from ..synthesis import CCCResult, SupconResult, ccc, forcible_layers, supcon
from ..synthesis.supcon import product
from ..des import symbolic_ops as SO
from .paper import PaperInstance, plant_symbolic, spec_symbolic

__all__ = ["literal_components", "supcon_modular", "ccc_modular", "literal_modular"]


def literal_components(inst: PaperInstance, ctx: Context | None = None):
    """``[(G_i, E_i)]`` of the literal reading, variables declared as in :func:`literal_models`."""
    ctx = ctx or Context()
    out = []
    for i in range(inst.size):
        num = inst.number(i)
        g = plant_symbolic(ctx, num, inst.steps, inst.start[i], inst.target[i], inst.priority_kind(i))
        s = spec_symbolic(ctx, num, inst.steps, inst.start[i], inst.target[i])
        out.append((g, SO.sync(SO.allevents(ctx, g), s, name=f"ALLxS{num}")))
    return out


def supcon_modular(components: list[tuple[SymbolicGenerator, SymbolicGenerator]], name: str = "V"):
    """``supcon(||G_i, ||E_i)`` by Theorem 1; returns ``(SupconResult, [SupconResult_i])``.
    The supervisor is the same generator the generic :func:`supcon` returns."""
    t0 = time.perf_counter()
    parts = [supcon(g, e, name=f"V{i + 1}") for i, (g, e) in enumerate(components)]
    G = SO.sync(*[g for g, _ in components], name="G")
    E = SO.sync(*[e for _, e in components], name="ALLxS")
    P = product(G, E, name)
    ctx = P.ctx
    z = ctx.true
    for r in reversed(parts):  # bottom-up: each conjunction costs the new block only
        z = r.supervisor.invariant & z
    V = P.restrict(z, name)
    states = [r.stats["states"] for r in parts]
    if any(s == 0 for s in states):
        V = P.restrict(ctx.false, name)
        stats = {"states": 0, "transitions": 0, "marked": 0}
    else:
        total = prod(states)
        stats = {
            "states": total,
            "transitions": sum(r.stats["transitions"] * (total // s) for r, s in zip(parts, states)),
            "marked": prod(r.stats["marked"] for r in parts),
        }
    stats.update(bdd_nodes=V.node_count(), set_nodes=ctx.node_count(z),
                 iterations=max((r.stats.get("iterations", 0) for r in parts), default=0),
                 seconds=time.perf_counter() - t0, method="modular")
    return SupconResult(V, stats), parts


def ccc_modular(V: SymbolicGenerator, parts: list[SupconResult], semantics: str = "preemptive") -> CCCResult:
    """CCC of ``V = ∏ V_i``: not forcible as soon as one ``V_i`` is not (Theorem 2); only
    when every component is forcible does it run the generic :func:`ccc` on ``V``."""
    t0 = time.perf_counter()
    for i, r in enumerate(parts):
        Vi = r.supervisor
        if Vi.init == Vi.ctx.false:
            return CCCResult(False, [], None, [], {"certificate": f"V{i + 1} is empty", "seconds": time.perf_counter() - t0})
        lay = forcible_layers(Vi, Vi.marked, semantics=semantics)
        if lay.rank(Vi.init) is None:
            return CCCResult(False, [], None, [], {
                "certificate": f"P{i + 1}'s initial state is not forcible in its own supervisor V{i + 1} "
                               f"(layers {lay.sizes()}), hence not in V (W(V) ⊆ ∏ W(V_i))",
                "component_layers": lay.sizes(), "seconds": time.perf_counter() - t0})
    return ccc(V, semantics)


# -- the literal model at scale: one small computation per distinct positioner ----------


def _template(steps: int, start: int, target: int, prio: str, semantics: str) -> dict:
    """``supcon`` and forcibility of one positioner in a context of its own (variables
    ``pos1, lvl1, cnt1``): positioners with equal ``(n, start, target, priority event)`` are
    equal up to renaming, and both algorithms commute with renaming."""
    ctx = Context()
    g = plant_symbolic(ctx, 1, steps, start, target, prio)
    e = SO.sync(SO.allevents(ctx, g), spec_symbolic(ctx, 1, steps, start, target), name="ALLxS1")
    r = supcon(g, e, name="V1")
    V = r.supervisor
    lay = forcible_layers(V, V.marked, semantics=semantics) if V.init != ctx.false else None
    return {"ctx": ctx, "z": V.invariant, "stats": r.stats,
            "forcible": lay is not None and lay.rank(V.init) is not None, "layers": lay.sizes() if lay else []}


def _transfer(u, target: Context, suffix: str, memo: dict) -> object:
    """Rebuild the template BDD ``u`` (bits ``pos1_k``, …) in ``target`` with the bits of
    positioner ``suffix`` (``pos{suffix}_k``): one ``ite`` per node, bottom-up."""
    bdd = target.bdd
    if u.var is None:
        return target.true if u == u.bdd.true else target.false
    neg = u.negated
    r = ~u if neg else u
    key = int(r)
    out = memo.get(key)
    if out is None:
        name = r.var
        base, bit = name.rsplit("_", 1)
        mapped = f"{base[:3]}{suffix}_{bit}"
        out = bdd.ite(bdd.var(mapped), _transfer(r.high, target, suffix, memo), _transfer(r.low, target, suffix, memo))
        memo[key] = out
    return ~out if neg else out


def literal_modular(inst: PaperInstance, ctx: Context | None = None, semantics: str = "preemptive"):
    """``(G, E, SupconResult, CCCResult)`` of the literal reading by Theorems 1 and 2,
    computing each distinct positioner once (``N`` up to thousands in seconds).

    The supervisor equals ``supcon(G, E)`` (Theorem 1; tests compare with the generic
    algorithm); the CCC verdict is exact when negative (Theorem 2) and otherwise falls
    back to the generic :func:`ccc` on the product.
    """
    t0 = time.perf_counter()
    ctx = ctx or Context()
    comps = literal_components(inst, ctx)
    G = SO.sync(*[g for g, _ in comps], name="G")
    E = SO.sync(*[e for _, e in comps], name="ALLxS")
    t1 = time.perf_counter()
    cache: dict[tuple, dict] = {}
    blocks = []
    for i in range(inst.size):
        key = (inst.steps, inst.start[i], inst.target[i], inst.priority_kind(i))
        if key not in cache:
            cache[key] = _template(*key, semantics)
        blocks.append(cache[key])
    z = ctx.true
    for i in reversed(range(inst.size)):  # bottom-up: each conjunction costs the new block only
        z = _transfer(blocks[i]["z"], ctx, str(inst.number(i)), {}) & z
    P = product(G, E, "V")
    V = P.restrict(z, "V")
    states = [b["stats"]["states"] for b in blocks]
    total = prod(states)
    stats = {
        "states": total,
        "transitions": sum(b["stats"]["transitions"] * (total // s) for b, s in zip(blocks, states)) if total else 0,
        "marked": prod(b["stats"]["marked"] for b in blocks) if total else 0,
        "bdd_nodes": V.node_count(), "set_nodes": ctx.node_count(z), "iterations": max(b["stats"]["iterations"] for b in blocks),
        "distinct_components": len(cache), "method": "modular", "build_seconds": t1 - t0,
        "seconds": time.perf_counter() - t1,
    }
    res = SupconResult(V if total else P.restrict(ctx.false, "V"), stats)
    t2 = time.perf_counter()
    bad = next((i for i, b in enumerate(blocks) if not b["forcible"]), None)
    if bad is not None:
        c = CCCResult(False, [], None, [], {
            "certificate": f"P{bad + 1}'s initial state is not forcible in its own supervisor "
                           f"(layers {blocks[bad]['layers']}), hence not in V (W(V) ⊆ ∏ W(V_i))",
            "seconds": time.perf_counter() - t2})
    else:
        c = ccc(res.supervisor, semantics)
    return G, E, res, c
