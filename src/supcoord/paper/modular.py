"""Exact decomposition of the literal model: supcon per positioner, CCC certificate.

In the literal reading the positioners share no events and no variables: the plant
is ``G = G_1 || … || G_N`` and the specification ``E = E_1 || … || E_N`` with
``E_i = allevents(G_i) || S_i`` over ``Σ_i`` (pairwise disjoint), so the product
``P = G × E`` is ``P_1 × … × P_N``.  Two facts make ``N`` small computations replace one
big one (both proven here and tested against the generic algorithms in
``tests/paper/test_paper.py``):

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
:func:`literal_modular` solves each distinct positioner once (:class:`Templates`, one
small shared context), moves its ``Z_i`` to positioner ``i``'s bits (:func:`transfer`)
and conjoins the blocks: the supervisor's state-set BDD is the sum of its blocks,
linear in ``N`` (docs/paper.md §6, benchmarks/results/paper.md).

**Theorem 2 (forcibility, necessary condition).** For ``V = ∏ V_i`` (disjoint
alphabets) and target ``T = ∏ T_i``, under either semantics of
:mod:`supcoord.synthesis.forcibility`, ``W(V) ⊆ ∏ W(V_i)``.  So if some ``q0_i`` is not
forcible in ``V_i``, ``q0`` is not forcible in ``V`` (the converse fails in general:
the counterexample of docs/forcibility.md, "The decomposition caveat", and the reason this is
only a certificate).

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
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (the seed paper).
"""

from __future__ import annotations

import time
from math import prod

from ..bdd.context import Context
from ..des import symbolic_ops as SO
from ..des.symbolic import SymbolicGenerator
from ..errors import InputError
from ..synthesis import CCCResult, SupconResult, ccc, forcible_layers, supcon
from ..synthesis.supcon import product
from .literal import PaperInstance, plant_symbolic, spec_symbolic

__all__ = ["literal_components", "supcon_modular", "ccc_modular", "Templates", "transfer", "literal_modular"]


def literal_components(inst: PaperInstance, ctx: Context | None = None):
    """``[(G_i, E_i)]`` of the literal reading, variables declared as in :func:`literal_models`."""
    ctx = ctx or Context()
    out = []
    for i in range(inst.size):
        if i % 64 == 63:
            _check_time(ctx, "literal build", positioner=i + 1)
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


class Templates:
    """``supcon`` and forcibility of each distinct literal positioner, computed once.

    Positioners with equal ``(steps, start, target, priority event)`` are equal up to
    renaming their variables, and ``supcon`` and the forcibility fixpoint commute with
    renaming; so each distinct key is solved once over the variables ``pos1, lvl1,
    cnt1`` of **one** small shared context (a CUDD manager costs tens of milliseconds to
    create; building hundreds of them dominated the run time) and its winning set is
    transferred to positioner ``i``'s bits by :func:`transfer`.  The shared context gets
    the caller's budget and progress callback, so ``--timeout``/``--max-nodes`` apply.
    """

    def __init__(self, steps: int, semantics: str = "preemptive", *, budget=None, progress=None, backend: str = "auto"):
        self.steps, self.semantics = steps, semantics
        self.ctx = Context(backend, budget=budget, progress=progress)
        for name, size in (("pos1", steps), ("lvl1", 3), ("cnt1", steps)):
            self.ctx.add_variable(name, size)
        self.cache: dict[tuple[int, int, str], dict] = {}

    def __len__(self) -> int:
        return len(self.cache)

    def get(self, start: int, target: int, prio: str) -> dict:
        """``{"z", "stats", "forcible", "layers", "rank"}`` of the positioner ``(start,
        target, prio)``: its supervisor's state set (over ``pos1, lvl1, cnt1``), its exact
        statistics, and whether its initial state is forcible in its own supervisor."""
        key = (start, target, prio)
        out = self.cache.get(key)
        if out is None:
            out = self.cache[key] = self._solve(*key)
        return out

    def _solve(self, start: int, target: int, prio: str) -> dict:
        ctx, n = self.ctx, self.steps
        g = plant_symbolic(ctx, 1, n, start, target, prio, declare=False)
        s = spec_symbolic(ctx, 1, n, start, target, declare=False)
        e = SO.sync(SO.allevents(ctx, g), s, name="ALLxS1")
        r = supcon(g, e, name="V1")
        V = r.supervisor
        if V.init == ctx.false:
            return {"z": ctx.false, "stats": r.stats, "forcible": False, "layers": [], "rank": None}
        lay = forcible_layers(V, V.marked, semantics=self.semantics)
        rank = lay.rank(V.init)
        return {"z": V.invariant, "stats": r.stats, "forcible": rank is not None, "layers": lay.sizes(), "rank": rank}


def transfer(u, source: Context, target: Context, suffix: str, memo: dict | None = None):
    """Rebuild ``u`` (a BDD of ``source`` over ``pos1, lvl1, cnt1``) in ``target`` over
    ``pos{suffix}, lvl{suffix}, cnt{suffix}``: one ``ite`` per node, bottom-up, so it costs
    ``O(|u|)`` whatever the size of ``target``.  Both contexts must order the bits of
    one positioner alike (they do: each declares ``pos, lvl, cnt`` in that order)."""
    bits = {}
    for base in ("pos", "lvl", "cnt"):
        sv, tv = source.vars[f"{base}1"], target.vars[f"{base}{suffix}"]
        if sv.size != tv.size:
            raise InputError(f"cannot transfer {base}1 (size {sv.size}) to {base}{suffix} (size {tv.size})",
                             value=f"{base}{suffix}")
        bits.update(zip(sv.bits, tv.bits))
    bdd, memo = target.bdd, {} if memo is None else memo

    def rebuild(f):
        if f.var is None:
            return target.true if f == f.bdd.true else target.false
        neg = f.negated
        r = ~f if neg else f
        key = int(r)
        out = memo.get(key)
        if out is None:
            out = bdd.ite(bdd.var(bits[r.var]), rebuild(r.high), rebuild(r.low))
            memo[key] = out
        return ~out if neg else out

    return rebuild(u)


def _check_time(ctx: Context, stage: str, **info) -> None:
    """``ctx.check_budget`` when the time budget has run out (so it raises), else nothing:
    the full check reads CUDD's statistics, which costs ~0.1 s in a manager with tens of
    thousands of variables; node budgets are checked by the fixpoints and at stage ends."""
    b = ctx.budget
    if b.timeout is not None and b.elapsed() > b.timeout:
        ctx.check_budget(stage, **info)


def _certificate(i: int, block: dict) -> str:
    if block["stats"]["states"] == 0:
        return f"V{i + 1} = supcon(G{i + 1}, allevents(G{i + 1}) || S{i + 1}) is empty, hence V is empty (Theorem 1)"
    return (f"P{i + 1}'s initial state is not forcible in its own supervisor V{i + 1} (forcible layers "
            f"{block['layers']}), hence not in V (Theorem 2: W(V) ⊆ ∏ W(V_i))")


def literal_modular(inst: PaperInstance, ctx: Context | None = None, semantics: str = "preemptive", *,
                    full: bool = False, templates: Templates | None = None, components: list | None = None):
    """``(G, E, SupconResult, CCCResult)`` of the literal reading by Theorems 1 and 2,
    computing each distinct positioner once (``N`` = thousands in seconds).

    The supervisor is the generator the generic :func:`supcon` returns (Theorem 1;
    ``tests/paper/test_paper.py`` compares the two), with exact statistics from the
    components' (``|V| = ∏ |V_i|``, ``|δ_V| = Σ_i |δ_{V_i}| ∏_{j≠i} |V_j|``).  The CCC
    verdict is exact when negative (Theorem 2; ``ccc.stats["certificate"]`` names the
    positioner) and otherwise comes from the generic :func:`ccc` on the product (``full``
    as there).  ``ctx.check_budget`` is called while the components are transferred.
    ``components`` (from :func:`literal_components` in ``ctx``) reuses built ones, so a
    test can run the generic algorithms on the very same ``G`` and ``E``.
    """
    t0 = time.perf_counter()
    ctx = ctx or Context()
    comps = literal_components(inst, ctx) if components is None else components
    G = SO.sync(*[g for g, _ in comps], name="G")
    E = SO.sync(*[e for _, e in comps], name="ALLxS")
    t1 = time.perf_counter()
    ctx.check_budget("literal build", positioners=inst.size)
    tpl = templates if templates is not None else Templates(inst.steps, semantics, budget=ctx.budget, progress=ctx.progress, backend=ctx.backend)
    if tpl.steps != inst.steps or tpl.semantics != semantics:
        raise InputError(f"templates for steps={tpl.steps}, {tpl.semantics} used on steps={inst.steps}, {semantics}",
                         value=(tpl.steps, tpl.semantics))
    blocks = [tpl.get(inst.start[i], inst.target[i], inst.priority_kind(i)) for i in range(inst.size)]
    t2 = time.perf_counter()
    z = ctx.true
    for i in reversed(range(inst.size)):  # bottom-up: each conjunction costs the new block only
        z = transfer(blocks[i]["z"], tpl.ctx, ctx, str(inst.number(i))) & z
        if i % 64 == 0:
            _check_time(ctx, "literal transfer", positioner=i + 1)
    ctx.check_budget("literal transfer", positioners=inst.size, set_nodes=ctx.node_count(z))
    P = product(G, E, "V")
    states = [b["stats"]["states"] for b in blocks]
    total = prod(states)
    V = P.restrict(z if total else ctx.false, "V")
    stats = {
        "states": total,
        "transitions": sum(b["stats"]["transitions"] * (total // s) for b, s in zip(blocks, states)) if total else 0,
        "marked": prod(b["stats"]["marked"] for b in blocks) if total else 0,
        "bdd_nodes": V.node_count(), "set_nodes": ctx.node_count(V.invariant),
        "iterations": max(b["stats"]["iterations"] for b in blocks),
        "distinct_components": len(tpl), "method": "modular",
        "build_seconds": t1 - t0, "template_seconds": t2 - t1, "seconds": time.perf_counter() - t1,
    }
    res = SupconResult(V, stats)
    t3 = time.perf_counter()
    bad = next((i for i, b in enumerate(blocks) if not b["forcible"]), None)
    if bad is not None:
        c = CCCResult(False, [], None, [], {"certificate": _certificate(bad, blocks[bad]), "decided_by": "theorem 2",
                                            "positioner": bad + 1, "component_layers": blocks[bad]["layers"],
                                            "seconds": time.perf_counter() - t3})
    else:
        c = ccc(V, semantics, full=full)
        c.stats["decided_by"] = "product"
    return G, E, res, c
