"""``supcon(G, E)``: the supremal controllable sublanguage, computed on state sets.

``G = (Q, Σ, δ, q0, Qm)`` is the plant with ``Σ = Σc ⊎ Σu``; ``E`` a specification
over (a subset of) ``Σ`` with TCT's meaning: an event of ``G`` that ``E`` does not
have, or does not define at a state, is disabled there (which is why the seed paper
writes ``allevents(G) || S`` to let the events ``S`` ignores pass).  With
``P = G × E`` the product over ``Σ`` (``δ_P((g, e), σ) = (δ_G(g, σ), δ_E(e, σ))``,
undefined where ``σ ∉ Σ_E``):

- ``B0 = {(g, e) ∈ Q_P : ∃ u ∈ Σu. δ_G(g, u)! ∧ ¬δ_P((g, e), u)!}`` — states where the
  specification would have to disable an uncontrollable event;
- ``Z_0 = Reach(P) \\ B0``, and until the second step removes nothing:
  ``Z := Z ∩ CoReach_Z(Qm)`` (nonblocking),
  ``Z := Z \\ UPre*(¬Z)`` with ``UPre*(X) = μY. X ∪ ⋃_{u∈Σu} Pre_u(Y)`` (controllability);
  then ``Z := Reach_Z(q0)``.  When the controllability step removes nothing, ``Z`` is
  closed under both steps, i.e. the greatest controllable and nonblocking subset of
  ``Reach(P) \\ B0``; the final ``Reach_Z(q0)`` keeps both properties (a path from a
  reachable state stays reachable) and is never needed inside the loop (an
  unreachable state lies on no path from a reachable one).  The explicit twin keeps
  the textbook loop with all three steps until nothing changes;
- the supervisor is ``P`` restricted to ``Z`` (empty when ``q0 ∉ Z``); it is trim and
  ``Lm(supervisor) = sup C(Lm(G) ∩ Lm(E))``, ``L(supervisor)`` its prefix closure.

**Without the reachable set** (``accessible=False``).  The loop's operator reads only
the future of a state (its paths to ``Qm``, its uncontrollable successors), so on any
set ``A`` closed under successors its greatest fixpoint is the one on the whole state
space restricted to ``A``: ``Z_A = Z_Q ∩ A``.  With ``A = Reach(P)``, the supervisor
computed on ``Q_P \\ B0`` without any forward search, ``P`` restricted to ``Z_Q``, has
the same initial state, the same reachable part and so the same languages; only its
unreachable states differ, and its exact sizes need :func:`accessible_part`.  This pays
where ``Reach(P)`` is the hard set: in the coupled paper model a positioner's collision
level remembers its neighbours' past, so ``Reach(P)`` takes 117,184 BDD nodes at
7 positioners, the controllable set over all states 2,012 (``docs/paper.md``).
Forcibility from ``q0`` is decided identically on both (:mod:`.forcibility` reads
successors only).

The command line follows libFAUDES's convention instead: a specification is first
lifted to the plant alphabet by self-loops (:func:`lift_spec`, ``InvProject``), then
``supcon`` is called.  :func:`supcon_naive` is the explicit twin.  :func:`supcon_flat`
is the same computation for components given as
:class:`~supcoord.des.flat.FlatGenerator` arrays with libFAUDES's convention (the
command line's explicit route for small flat problems): the explicit product, then the
same loop with each step a reachability on arrays.

References
----------
- P. J. Ramadge, W. M. Wonham, Supervisory control of a class of discrete event
  processes, SIAM J. Control Optim. 25(1), 1987.
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer
  2019, §3.5–3.7 (supcon, TCT).
- A. Vahidi, M. Fabian, B. Lennartson, Efficient supervisory synthesis of large
  systems, Control Engineering Practice 2006 (symbolic, event-partitioned).
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (the seed paper: ``V = supcon(G, allevents(G) || S)``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, TypedDict

import numpy as np

from ..des import explicit_ops as X
from ..des import symbolic_ops as S
from ..des.flat import FlatGenerator, renumber
from ..des.flat_ops import bfs_order
from ..des.flat_product import Graph, flat_sync
from ..des.generator import Generator
from ..des.symbolic import SymbolicGenerator
from ..des.symbolic_export import state_names
from ..errors import InputError
from ..progress import summary_html, summary_repr
from .checks import check_deterministic
from .effort import Effort, EffortMeter
from .product import (
    accessible_pairs,
    check_alphabets,
    product,
    product_naive,
    uncontrollable_blocked,
    uncontrollable_blocked_naive,
)
from .reachability import DEFAULT_METHOD, coreachable, coreachable_naive, reachable, reachable_naive

__all__ = ["SupconResult", "SupervisorCounts", "FlatSupconStats", "supcon", "accessible_part", "supcon_naive",
           "supcon_flat", "lift_spec", "product", "product_naive", "check_alphabets"]


class SupervisorCounts(TypedDict):
    """The sizes of a symbolic supervisor: exact counts (``None`` when computed without
    the reachable set, or ``transitions`` when not asked for), BDD sizes in nodes."""

    states: int | None
    transitions: int | None
    marked: int | None
    bdd_nodes: int
    set_nodes: int
    accessible: bool


class FlatSupconStats(TypedDict):
    """The statistics of :func:`supcon_flat` (those of :class:`SupconResult` that an
    explicit computation has; ``bdd_nodes`` and ``set_nodes`` 0, ``seconds`` in s)."""

    states: int
    transitions: int
    marked: int
    bdd_nodes: int
    set_nodes: int
    iterations: int
    seconds: float


@dataclass
class SupconResult:
    """The supervisor (``G × E`` restricted to its trim controllable set) and statistics:
    ``states``, ``transitions``, ``marked`` (exact), ``bdd_nodes`` (the supervisor's
    shared DAG), ``set_nodes`` (its state set), ``iterations``, ``seconds``; ``effort``: seconds per
    fixpoint stage and CUDD's counters (:class:`~supcoord.synthesis.effort.Effort`)."""

    supervisor: SymbolicGenerator
    stats: dict[str, Any] = field(default_factory=dict)
    effort: Effort | None = None  # where the time and the BDD work went (also stats["effort"])

    @property
    def empty(self) -> bool:
        return self.supervisor.init == self.supervisor.ctx.false

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: the supervisor's name and the statistics' numbers."""
        keep = ("states", "marked", "transitions", "bdd_nodes", "iterations", "seconds")
        out: dict[str, Any] = {"supervisor": getattr(self.supervisor, "name", "?")}
        out.update({k: _short(self.stats[k]) for k in keep if k in (self.stats or {})})
        return out

    def __repr__(self) -> str:
        return summary_repr("SupconResult", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("SupconResult", self.summary())


def _short(value: Any) -> Any:
    """A count of more than 15 digits as ``~1.2e+40`` (the exact count can have thousands)."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 50:
        return f"~{float(value):.3g}" if value.bit_length() < 1000 else f"~10^{value.bit_length() * 0.30103:.0f}"
    return round(value, 3) if isinstance(value, float) else value


def lift_spec(plant, E, name: str | None = None):
    """``E`` with a self-loop at every state for each plant event it lacks
    (libFAUDES ``InvProject``; TCT ``selfloop``).  ``plant`` is a generator (explicit or
    symbolic) or an iterable of :class:`Event`; ``E`` explicit or symbolic, and the
    result has the same type as ``E``."""
    if not isinstance(E, (Generator, SymbolicGenerator)):
        raise InputError(f"lift_spec expects a Generator or SymbolicGenerator, got {type(E).__name__}", value=E)
    alphabet = plant.alphabet if isinstance(plant, (Generator, SymbolicGenerator)) else list(plant)
    missing = [e for e in alphabet if e.name not in E.events]
    if isinstance(E, Generator):
        return X.selfloop(E, missing, name=name or E.name)
    return S.selfloop(E, missing, name=name or E.name)


# -- symbolic ------------------------------------------------------------------


def supcon(G: SymbolicGenerator, E: SymbolicGenerator, *, name: str = "V", method: str = DEFAULT_METHOD,
           count_transitions: bool = True, accessible: bool = True) -> SupconResult:
    """The supremal controllable and nonblocking supervisor of ``G`` for ``E`` (TCT meaning).

    ``V = G × E`` restricted to the greatest controllable and nonblocking subset of
    ``Reach(G × E)`` (the module docstring gives the fixpoints); ``Lm(V)`` is the
    supremal controllable sublanguage of ``Lm(G) ∩ Lm(E)``.

    Parameters
    ----------
    G : SymbolicGenerator
        The plant, deterministic; its alphabet ``Σ = Σc ⊎ Σu`` (not empty).
    E : SymbolicGenerator
        The specification, deterministic, in ``G``'s :class:`~supcoord.bdd.Context` with
        variables of its own, over a subset of ``Σ``.  An event of ``G`` that ``E`` lacks
        is disabled (TCT's meaning; :func:`lift_spec` gives libFAUDES's).
    name : str, optional
        The supervisor's name.
    method : {"saturation", "chaining", "bfs"}, optional
        How the reachability fixpoints are computed (same result, other time and memory).
    count_transitions : bool, optional
        ``False`` leaves ``stats["transitions"]`` as ``None``: the exact count
        ``Σ_σ |Z ∩ En_σ|`` takes one ``Pre`` and one count per event, a noticeable share
        of the run time of products with thousands of events.
    accessible : bool, optional
        ``False`` computes the supervisor on the whole state space, without
        ``Reach(P)`` (module docstring): the same languages, initial state and reachable
        part, but unreachable states too, so ``stats`` leaves ``states``,
        ``transitions`` and ``marked`` as ``None`` (``stats["accessible"]`` says which);
        :func:`accessible_part` gives the trim supervisor and its counts.

    Returns
    -------
    SupconResult
        ``supervisor`` (symbolic; no initial state when the supervisor is empty) and
        ``stats``: ``states``, ``transitions``, ``marked`` (exact counts),
        ``bdd_nodes`` (the supervisor's shared DAG, nodes), ``set_nodes`` (its state
        set, nodes), ``iterations`` (passes of the nonblocking/controllability loop),
        ``seconds`` (wall-clock time, s), ``accessible``, ``effort`` (seconds per stage
        and CUDD's counters, also as ``effort``).

    Raises
    ------
    AlphabetError
        ``G``'s alphabet is empty, or ``E`` has an event ``G`` lacks or with another
        controllability (:func:`check_alphabets`).
    NondeterminismError
        ``G`` or ``E`` is nondeterministic.
    InputError
        ``E`` lives in another context, shares variables with ``G``, or ``method`` is
        unknown.
    BudgetExceeded
        The context's node or time budget ran out (:class:`~supcoord.bdd.Budget`).

    See Also
    --------
    supcon_naive : the explicit twin.
    supcon_flat : the same on arrays, with libFAUDES's convention.
    supcoord.synthesis.ccc.ccc : the Complete Coordination Checker of the result.

    References
    ----------
    .. [1] P. J. Ramadge, W. M. Wonham, "Supervisory control of a class of discrete
       event processes", SIAM J. Control Optim. 25(1), 206-230, 1987.
    .. [2] W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*,
       Springer, 2019, sec. 3.5-3.7.
    .. [3] M. Macktoobian, D. Gillet, J.-P. Kneib, "Supervisory coordination of robotic
       fiber positioners in multi-object spectrographs", IFAC-PapersOnLine 52(3), 2019,
       doi:10.1016/j.ifacol.2019.06.011.

    Examples
    --------
    A machine that may start (``a``) and then finishes (``u``, uncontrollable), or may
    break down (``b``) into a state it never leaves; the specification allows every
    event, so the supervisor only removes the blocking ``b``:

    >>> from supcoord.bdd import Context
    >>> from supcoord.des.generator import Event, Generator
    >>> from supcoord.des.symbolic import from_explicit, to_explicit
    >>> a, b, u = Event("a", True), Event("b", True), Event("u", False)
    >>> G0 = Generator(3, [a, b, u], [(0, "a", 1), (1, "u", 0), (0, "b", 2)], 0, [0], name="G")
    >>> E0 = Generator(1, [a, b, u], [(0, "a", 0), (0, "u", 0), (0, "b", 0)], 0, [0], name="E")
    >>> ctx = Context()
    >>> result = supcon(from_explicit(ctx, G0), from_explicit(ctx, E0))
    >>> result.stats["states"], result.stats["transitions"], result.stats["marked"]
    (2, 2, 1)
    >>> sorted(to_explicit(result.supervisor).enabled(0))
    ['a']
    """
    t0 = time.perf_counter()
    ctx = G.ctx
    with EffortMeter(ctx) as meter:
        with meter.stage("product"):
            P = product(G, E, name)
            check_deterministic(G)
            check_deterministic(E)
        unc = P.uncontrollable
        with meter.stage("reachable"):
            universe = reachable(P, method=method) if accessible else P.invariant  # Reach(P), or Q_P
            z = universe & ~uncontrollable_blocked(G, P)  # universe \ B0
        zold, i = None, 0
        while z != zold:  # until the controllability step removes nothing
            inside = None if z == P.invariant else z  # (unconstrained: saturation may use its local closures)
            with meter.stage("nonblocking"):
                zold = coreachable(P, P.marked & z, within=inside, method=method)  # Z ∩ CoReach_Z(Qm)
            with meter.stage("controllable"):
                bad = universe & ~zold
                z = zold & ~coreachable(P, bad, within=universe, method=method, events=unc)  # Z \ UPre*(¬Z)
            i += 1
            ctx.check_budget("supcon", iteration=i, z_nodes=ctx.node_count(z))
        with meter.stage("accessible"):
            if accessible and z != universe:  # (Z = Reach(P) is its own Reach_Z(q0))
                z = reachable(P, P.init & z, within=z, method=method)  # Reach_Z(q0)
            V = P.restrict(z, name)
        with meter.stage("counts"):
            stats = {"iterations": i, **_counts(V, count_transitions, accessible)}
        effort = meter.result()
    stats["seconds"] = time.perf_counter() - t0
    stats["effort"] = effort.as_dict()
    return SupconResult(V, stats, effort)


def _counts(V: SymbolicGenerator, count_transitions: bool, accessible: bool) -> SupervisorCounts:
    """The sizes of a supervisor; exact counts only for an accessible one."""
    ctx = V.ctx
    return {
        "states": V.count_states() if accessible else None,
        "transitions": V.count_transitions() if accessible and count_transitions else None,
        "marked": ctx.count(V.marked, V.variables) if accessible else None,
        "bdd_nodes": V.node_count(),
        "set_nodes": ctx.node_count(V.invariant),
        "accessible": accessible,
    }


def accessible_part(result: SupconResult, *, method: str = DEFAULT_METHOD,
                    count_transitions: bool = True) -> SupconResult:
    """The trim supervisor of a :func:`supcon` result computed with ``accessible=False``:
    its states reachable from ``q0`` (``Reach_Z(q0)``), with the exact counts; the
    result of ``supcon(G, E)`` itself.  An accessible result is returned as it is."""
    if result.stats.get("accessible", True):
        return result
    t0 = time.perf_counter()
    V = result.supervisor
    z = reachable(V, V.init, method=method)  # Reach_Z(q0)
    W = V.restrict(z, V.name)
    stats = dict(result.stats)
    stats.update(_counts(W, count_transitions, True))
    stats["seconds"] = result.stats["seconds"] + time.perf_counter() - t0
    return SupconResult(W, stats)


# -- explicit twin ---------------------------------------------------------------


def supcon_naive(G: Generator, E: Generator, name: str = "V") -> Generator:
    """Explicit ``supcon`` with the same meaning as :func:`supcon`; the result is trim."""
    P = product_naive(G, E, name)
    if P.init is None:
        return P
    pairs, _ = accessible_pairs(G, E)  # P's states, in P's numbering
    b0 = uncontrollable_blocked_naive(G, E, pairs)
    everything = set(range(P.n_states))
    z, zold = everything - b0, None
    while z != zold:
        zold = z
        z = coreachable_naive(P, target=P.marked & z, within=z)  # Z ∩ CoReach_Z(Qm)
        z = z - coreachable_naive(P, target=everything - z, events=G.uncontrollable)  # Z \ UPre*(¬Z)
        z = reachable_naive(P, within=z)  # Reach_Z(q0)
    return X.restrict(P, z, name)


# -- flat explicit components ------------------------------------------------------


def supcon_flat(plants: list[FlatGenerator], specs: list[FlatGenerator], *, name: str = "V",
                labels: list[str] | None = None, check=None) -> tuple[FlatGenerator, FlatSupconStats]:
    """:func:`supcon` of ``sync(plants)`` for ``sync(specs)`` lifted to the plant alphabet
    (a specification leaves the events it lacks free), on the explicit product.

    Returns the supervisor, numbered breadth-first from its initial state with events in
    alphabet order and its states named ``"label_i=q_i,…"`` (``labels``: one per
    component, plants then specifications; one-state components are left out): the
    generator :func:`~supcoord.des.symbolic.to_explicit` gives for the symbolic
    supervisor of the same components with those variable names.  Statistics as
    :class:`SupconResult` (``bdd_nodes`` 0).  ``check(stage, **info)`` is called
    between steps (a budget)."""
    t0 = time.perf_counter()
    comps = list(plants) + list(specs)
    labels = labels or [f"G{i}" for i in range(len(comps))]
    P = flat_sync(comps, check)
    n = P.n_states
    plant_ids, spec_ids = range(len(plants)), range(len(plants), len(comps))
    b0 = np.zeros(n, dtype=bool)
    unc = [g for g, e in enumerate(P.events) if not e.controllable]
    for u in unc:
        b0 |= P.enabled(u, plant_ids) & ~P.enabled(u, spec_ids)  # G enables u, the specification not
    marked = P.marked()
    unc_edges = np.isin(P.ev, unc)
    graph = Graph(n, P.src, P.dst)
    z, zold, i = ~b0, None, 0
    while zold is None or (z != zold).any():  # until the controllability step removes nothing
        zold = graph.reach(marked & z, within=z, backwards=True)  # Z ∩ CoReach_Z(Qm)
        z = zold & ~graph.reach(~zold, edges=unc_edges, backwards=True)  # Z \ UPre*(¬Z)
        i += 1
        if check is not None:
            check("supcon", iteration=i)
    start = np.zeros(n, dtype=bool)
    start[:1] = True
    z = graph.reach(start, within=z)  # Reach_Z(q0)
    keep = z[P.src] & z[P.dst]
    whole = FlatGenerator(name, P.events, n, P.src[keep], P.ev[keep], P.dst[keep], 0,
                          np.flatnonzero(marked & z), None)
    order = bfs_order(n, whole.src, whole.ev, whole.dst, 0) if n and z[0] else np.zeros(0, dtype=np.int64)
    shown = [j for j, c in enumerate(comps) if c.n_states > 1]
    names = state_names([labels[j] for j in shown], [P.states[order, j] for j in shown]) if len(order) else None
    V = renumber(whole, order, name, names)
    stats: FlatSupconStats = {"states": V.n_states, "transitions": V.n_transitions, "marked": len(V.marked),
                              "bdd_nodes": 0, "set_nodes": 0, "iterations": i, "seconds": time.perf_counter() - t0}
    return V, stats
