"""Local closures: a write group of events fired to its local fixpoint in one image.

Events whose write sets overlap form a *write group* ``Γ`` (union–find over
the write sets; in an open-component product, one component with its observer, e.g.
a positioner's ``pos, lvl`` and its specification's ``cnt``).  The group's steps are
replaced by one step with the transitive closure of their union relation, everything
the group only reads held fixed::

    R_Γ = ⋁_{σ∈Γ} R_σ ∧ I_{W_Γ \\ W_σ}          (the frame of W_Γ made explicit)
    R_Γ⁺ = μT. R_Γ ∨ T∘T                       (iterative squaring)

so one image moves a component as far as its own events can take it while its
neighbours stand still (*accelerated* or *saturated* images).  The fixpoint is the
same: ``R_σ ⊆ R_Γ⁺ ⊆ (⋁_σ R_σ)⁺``.  It is exact only if the intermediate states of a
local run lie in ``Q``: a group is accelerated only where every one of its steps maps
``Q`` into ``Q`` (``Img_σ(Q) ⊆ Q``, checked once), and such a step then also skips the
``∩ Q`` of every image.  The third copy of the written bits that ``T∘T`` needs lives in
a scratch CUDD manager holding only the groups' supports (copied there and back), so
the main manager never sees it.  A group writing more than ``_CLOSURE_BITS`` bits, or
whose closure grows past ``_CLOSURE_GROWTH`` × its relation, keeps its plain steps.

**The closures' own work is bounded** (``max_work``): squaring can cost far more than
the plain steps it replaces even where every operand stays small (on ``machine_line(8)``
one ``AndAbstract`` of two 1,816-node operands took 120 million computed-table lookups,
~100 s, to return 1,414 nodes).  The scratch manager gives up once its operations have
taken ``max_work`` computed-table lookups (:class:`~supcoord.bdd.cudd_work.WorkLimit`,
CUDD's count of recursive steps: the same on every machine); the group being closed
then, and every group not yet closed, keep their plain steps.  A single write group
holding every step is not closed at all: its closure is the whole transition relation's,
a harder problem than the reachability it would serve.
On the coupled paper model (issue 15) this cuts the images of ``Reach(G × E)`` 10–35×
and its time ~2× at 5–6 positioners (benchmarks/results/coupled.md).

References
----------
- G. Ciardo, R. Marmorstein, R. Siminiceanu, Saturation unbound, TACAS 2003 (firing
  an event to its local fixpoint; transitive closure of local relations).
- J. R. Burch, E. M. Clarke, K. L. McMillan, D. L. Dill, L. J. Hwang, Symbolic model
  checking: 10^20 states and beyond, LICS 1990 (transitive closure by iterative
  squaring).
"""

from __future__ import annotations

import sys

from dataclasses import replace

from ..bdd.context import BDD, Context
from ..bdd.cudd_work import WorkLimit, cache_lookups
from .effort import add_closure_work
from .image_step import ImageStep

__all__ = ["write_groups", "local_closures", "work_done"]

_CLOSURE_BITS = 16  # a group writing more bits keeps its plain steps
_CLOSURE_GROWTH = 32  # … and so does one whose closure exceeds this × its relation's nodes


def work_done(ctx: Context) -> int | None:
    """The computed-table lookups of ``ctx``'s manager so far (CUDD's count of operation
    steps, :func:`~supcoord.bdd.cudd_work.cache_lookups`), or ``None`` without CUDD."""
    if ctx.backend != "cudd" or not ctx.fast_count:
        return None
    import dd.cudd as cudd

    return cache_lookups(ctx.bdd, cudd)


def write_groups(steps: list[ImageStep]) -> list[list[ImageStep]]:
    """The steps grouped by overlapping write sets (union–find: two steps whose write
    sets share a variable are in one group), each group in first-seen order."""
    parent: dict[str, str] = {}

    def find(v: str) -> str:
        while parent.setdefault(v, v) != v:
            parent[v] = parent[parent[v]]  # path halving
            v = parent[v]
        return v

    for s in steps:
        first, *rest = sorted(s.writes)
        for v in rest:
            parent[find(v)] = find(first)
    groups: dict[str, list[ImageStep]] = {}
    for s in steps:
        groups.setdefault(find(min(s.writes)), []).append(s)
    return list(groups.values())


def local_closures(ctx: Context, steps: list[ImageStep], inside: BDD, max_work: int | None = None) -> list[ImageStep]:
    """Replace each write group whose steps all map ``inside`` into itself by one step
    with the transitive closure ``R_Γ⁺`` of the group's relation (module docstring); the
    other groups keep their steps, with ``∩ inside`` left out where ``Img_σ(inside) ⊆
    inside``.  ``max_work`` bounds the computed-table lookups (CUDD's operation steps) of
    all closures together; groups not closed within it keep their plain steps (``None``:
    no bound).  Needs CUDD (the scratch manager); with another backend nothing changes."""
    if ctx.backend != "cudd" or not steps:
        return steps
    closed = [s for s in steps if s.raw_image(ctx, inside) & ~inside == ctx.false]  # Img_σ(Q) ⊆ Q
    closed_ids = {id(s) for s in closed}
    steps = [s if id(s) not in closed_ids else replace(s, clip=False) for s in steps]
    out: list[ImageStep] = []
    todo: list[tuple[list[ImageStep], tuple[str, ...], BDD]] = []
    groups = write_groups(steps)
    if len(groups) == 1:  # the closure of the whole relation: harder than the reachability it serves
        return steps
    for group in groups:
        writes = tuple(sorted(frozenset().union(*(s.writes for s in group))))
        if any(s.clip for s in group) or len(ctx.bits(writes)) > _CLOSURE_BITS:
            out.extend(group)
            continue
        rel = ctx.false
        for s in group:  # R_Γ = ⋁_σ R_σ ∧ I_{W_Γ \ W_σ}
            rel |= s.relation & ctx.identity(sorted(set(writes) - s.writes))
        todo.append((group, writes, rel))
    if not todo:
        return out
    for (group, writes, rel), plus in zip(todo, _closures(ctx, [(ctx.bits(w), r) for _, w, r in todo], max_work)):
        if plus is None:  # grew too large: the plain steps
            out.extend(group)
            continue
        first = group[0]
        bits, pbits = tuple(ctx.bits(writes)), tuple(ctx.bits(writes, primed=True))
        qbits, rbits = (bits, pbits) if first.forward else (pbits, bits)
        support = frozenset().union(*(s.support for s in group))
        out.append(ImageStep("|".join(s.event for s in group), plus, qbits, ctx.identity(writes), rbits, first.forward,
                         frozenset(writes), support, False))
    return out


def _closures(ctx: Context, relations: list[tuple[list[str], BDD]], max_work: int | None = None) -> list[BDD | None]:
    """``R⁺`` of each ``(written bits, R)`` by iterative squaring, ``T := T ∨ T∘T`` with
    ``(T∘T)(x, x') = ∃m. T(x, m) ∧ T(m, x')`` over the written bits only, in one scratch
    CUDD manager holding the relations' bits in the main order and a third copy ``m``
    right below each primed written bit; ``None`` where ``R⁺`` outgrows
    ``_CLOSURE_GROWTH`` × ``R``, for every relation not closed within ``max_work``
    computed-table lookups of the scratch manager, and for all when no scratch manager can
    be had."""
    import dd.cudd as cudd

    bdd = ctx.bdd
    written = {b for bits, _ in relations for b in bits}
    needed = set(written) | {b + "'" for b in written}
    for _, r in relations:
        needed |= bdd.support(r)
    hook = sys.unraisablehook  # dd's __dealloc__ of a manager that failed to start only complains
    sys.unraisablehook = lambda unraisable: None
    try:
        scratch = cudd.BDD(initial_cache_size=2**14)
    except RuntimeError:  # no memory for a second manager (a memory cap): the plain steps serve
        add_closure_work(0, 0, len(relations))
        return [None] * len(relations)
    finally:
        sys.unraisablehook = hook
    mid = {}
    for v in sorted(needed, key=bdd.level_of_var):
        scratch.declare(v)
        if v.endswith("'") and v[:-1] in written:
            mid[v[:-1]] = v + "'"  # x'' (a name the main manager never declares)
            scratch.declare(mid[v[:-1]])
    out: list[BDD | None] = []
    unbounded = 1 << 62  # (counted, never reached)
    with WorkLimit(scratch, cudd, (unbounded if max_work is None else max_work) if ctx.fast_count else None) as limit:
        for bits, r in relations:
            try:
                out.append(_square(ctx, scratch, cudd, bits, r, mid))
            except ValueError:  # CUDD gave up (the work limit): this and the rest keep their steps
                if not limit.exceeded:
                    raise
                break
        used = limit.used()
    out += [None] * (len(relations) - len(out))
    add_closure_work(used, sum(t is not None for t in out), sum(t is None for t in out))
    return out


def _square(ctx: Context, scratch, cudd, bits: list[str], r: BDD, mid: dict[str, str]) -> BDD | None:
    """``R⁺`` of one relation in the scratch manager (:func:`_closures`), copied back."""
    to_mid_target = {b + "'": mid[b] for b in bits}  # T(x, m): x' → m
    to_mid_source = {b: mid[b] for b in bits}  # T(m, x'): x → m
    mids = [mid[b] for b in bits]
    t = cudd.copy_bdd(r, scratch)
    cap = _CLOSURE_GROWTH * max(1, ctx.node_count(r))
    while True:
        t2 = t | cudd.and_exists(scratch.let(to_mid_target, t), scratch.let(to_mid_source, t), mids)
        if t2 == t:
            return cudd.copy_bdd(t, ctx.bdd)
        if len(t2) > cap:
            return None
        t = t2
