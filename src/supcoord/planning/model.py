"""The symbolic coordination model of a geometric problem: guarded single-joint moves.

For a problem with positioners ``P``, kinematics with joints ``J`` and neighbour pairs
``N ⊆ P × P`` (:mod:`supcoord.geometry.collision`), the model over a set of *members* ``S ⊆ P`` (the
others frozen at a configuration ``c``) is the generator

- variables ``x_{p,j} ∈ {0 … steps_j − 1}`` for ``p ∈ S``, ``j ∈ J`` (``q{p}`` for rotary,
  ``a{p}``/``b{p}`` for alpha-beta), declared in a geometry-aware order
  (:mod:`.graph_order`: reverse Cuthill–McKee over the conflict graph by default);
- one controllable event ``σ = (p, j, δ)`` per member and move (``plan.event_name``:
  ``v3``, ``wa0``, …) that writes only ``x_{p,j}``::

      R_σ(x, x'_{p,j}) = [x'_{p,j} = step_{j,δ}(x_{p,j})]                (hard stops: no step)
                        ∧ ⋀_{q ∈ S, (p,q) ∈ N}  ¬B_{p,m}(x_p, x_q)
                        ∧ ⋀_{q ∉ S, (p,q) ∈ N}  ¬B_{p,m}(x_p, c_q)        (frozen: a unary guard)

  with ``B_{p,m}`` the symmetrised blocked table of the move ``m`` of ``p`` past ``q``
  (:mod:`.guards`: the configuration graph is undirected, and collision-freedom
  needs no state invariant);
- ``q0 = c|_S`` (or the start), ``Qm = {target|_S}``, invariant: the valid codes.

Each pair guard is turned into a BDD on the actual bits from its table
(:func:`.guards.table_bdd`); on fine lattices the other pairs of the same geometry get it by
renaming the variables (the same function: ~1 ms against 10–40 ms from the table at
36 × 19 positions; :data:`RENAME_MIN_ENTRIES`).  Frozen neighbours' guards are rows of the
same tables.  The model of the whole grid holds every positioner in one
:class:`~supcoord.bdd.Context`, each declared when a window, guard or state first uses it
(:meth:`CoordinationModel.declare`, at its place in the order); a window's own manager copies
its pair guards from it (``guards_from``) instead of building them again, or renames one it
already has.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (positioners as DES).
- R. E. Bryant, Graph-based algorithms for Boolean function manipulation, 1986 (the relations).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field, replace
from typing import Any, Iterable, Sequence

import numpy as np

from ..bdd.context import BDD, Budget, Context
from ..des.generator import Event
from ..des.symbolic import EventRelation, SymbolicGenerator
from ..errors import InputError, ModelError
from ..problems.plan import event_name
from ..problems.problem import Problem
from .graph_order import cutwidth_order, hex_order, rcm_order
from .guards import blocked_column, blocked_table, conflict_graph, table_bdd, var_names

__all__ = ["CoordinationModel", "GuardedSystem", "GuardedMove"]

#: largest cluster of a merged event relation, in BDD nodes (:meth:`GuardedSystem.relation`):
#: guards are conjoined into one conjunct while it stays at most this size; a guard already
#: larger stays a conjunct of its own.  The measurements behind the value (500 against 2000 and
#: 5000) are in benchmarks/results/cluster_nodes.md
CLUSTER_NODES = 500
#: pair guards of tables with at least this many entries are renamed from the first guard of
#: their geometry (:meth:`CoordinationModel.pair_guard`): dd's renaming costs time in the
#: manager's declared bits (~1 ms at 127 robots, ~10 ms at DESI's 5,167), building from a
#: table in its entries (0.2 ms at 13 × 7, 10–40 ms at 36 × 19)
RENAME_MIN_ENTRIES = 2**16


class CoordinationModel:
    """Every positioner's variables in one context (declared when first used), guards cached per
    (positioner, move, neighbour).

    ``order``: ``"rcm"`` (default), ``"hex"`` (layout order), ``"cutwidth"``
    (:func:`.graph_order.cutwidth_order`, for windows) or an explicit permutation;
    ``members``: declare only these positioners (a window's own manager, its variables in
    the window's own reverse Cuthill–McKee order — a BDD's size depends only on the
    relative order of its support, and a window's members sit far apart in any order
    of the whole grid); ``guards_from``: a model declaring them too, whose pair guards are
    copied instead of built again from the tables (the windows of one run share them: at
    36 × 19 positions a guard costs ~40 ms from its table, ~2 ms to copy).
    :meth:`generator` builds the symbolic generator of a window (members move, the
    others are frozen at ``frozen``); :meth:`decode` reads a state back.
    """

    def __init__(self, problem: Problem, *, order: Any = "rcm", backend: str = "auto",
                 budget: Budget | None = None, progress: Any = None, reordering: bool = False,
                 members: Iterable[int] | None = None, guards_from: "CoordinationModel | None" = None):
        self.problem = problem
        self.guards_from = guards_from
        self.kin = problem.kinematics
        universe = list(range(problem.n)) if members is None else sorted(set(int(p) for p in members))
        if isinstance(order, str):
            if order not in ("rcm", "hex", "cutwidth"):
                raise InputError(f"unknown variable order {order!r} (use rcm, hex or cutwidth)", value=order)
            if order == "cutwidth":
                self.order = cutwidth_order(problem, universe)
            else:
                keep = set(universe)
                self.order = rcm_order(problem, members) if order == "rcm" else hex_order(problem)
                self.order = [p for p in self.order if p in keep]
        else:
            self.order = [int(p) for p in order]
            if sorted(self.order) != universe:
                raise InputError("order must be a permutation of the positioners", value=order)
        self.ctx = Context(backend, budget=budget, progress=progress, reordering=reordering)
        self._rank = {p: i for i, p in enumerate(self.order)}
        self._declared: list[int] = []  # ranks of the positioners declared so far, sorted
        self._declared_set: set[int] = set()
        #: a positioner's variables are declared when first used, at their place in ``order``
        #: (CUDD inserts them at a level); another backend, or dynamic reordering, gets all at once
        self._lazy = self.ctx.backend == "cudd" and not reordering
        if not self._lazy:
            for p in self.order:
                self.declare(p)
        self.adj = conflict_graph(problem)
        self.moves = self.kin.moves()
        self._pair_guard: dict[tuple[int, int, int], BDD] = {}
        #: (pair geometry key, side, move) → (variables, guard): the first guard built from
        #: that blocked table; pairs of equal geometry get it renamed
        self._guard_by_geometry: dict[tuple, tuple[list[str], BDD]] = {}
        self._unary_guard: dict[tuple, BDD] = {}
        self._step: dict[tuple[int, int], BDD] = {}
        self._identity: dict[str, BDD] = {}

    # -- pieces ------------------------------------------------------------------
    def declare(self, p: int) -> None:
        """Declare ``p``'s variables unless they are: below those of the declared positioners
        before ``p`` in :attr:`order`, above those after it, so every BDD is the one a manager
        declaring all positioners up front builds.  Memory grows with the positioners the
        search touches (CUDD keeps a unique subtable per bit: ~107 KiB per alpha-beta robot).

        Raises
        ------
        ModelError
            ``p`` is not one of the model's positioners."""
        if p in self._declared_set:
            return
        rank = self._rank.get(p)
        if rank is None:
            raise ModelError(f"positioner {p!r} is not declared in this model", value=p)
        at = bisect.bisect_left(self._declared, rank)
        level = None
        if self._lazy:
            level = at * sum(2 * max(1, (jt.steps - 1).bit_length()) for jt in self.kin.joints)
        for name, jt in zip(var_names(self.problem, p), self.kin.joints):
            var = self.ctx.add_variable(name, jt.steps, level)
            if level is not None:
                level += 2 * len(var.bits)
        self._declared.insert(at, rank)
        self._declared_set.add(p)

    @property
    def declared(self) -> int:
        """How many positioners have their variables declared."""
        return len(self._declared_set)

    def _shape(self) -> tuple[int, ...]:
        return self.kin.shape

    def step_relation(self, p: int, m: int) -> BDD:
        """``x'_{p,j} = step(x_{p,j})`` for move ``m = (j, δ)`` (no step past a hard stop)."""
        key = (p, m)
        r = self._step.get(key)
        if r is None:
            self.declare(p)
            joint, delta = self.moves[m]
            jt = self.kin.joints[joint]
            name = var_names(self.problem, p)[joint]
            r = self.ctx.false
            column = np.zeros((jt.steps, self.kin.n_joints), dtype=int)
            column[:, joint] = np.arange(jt.steps)
            nxt, ok = self.kin.step_array(column, joint, delta)
            for i in np.nonzero(ok)[0].tolist():
                r |= self.ctx.eq(name, i) & self.ctx.eq(name, int(nxt[i, joint]), primed=True)
            self._step[key] = r
        return r

    def pair_guard(self, p: int, m: int, k: int, q: int, side: int) -> BDD:
        """``¬B_{p,m}(x_p, x_q)`` for the conflict pair ``k`` (``side`` = ``p``'s side)."""
        key = (p, m, q)
        g = self._pair_guard.get(key)
        if g is None:
            self.declare(p)
            self.declare(q)
            names = var_names(self.problem, p) + var_names(self.problem, q)
            shared = self.problem.pair_geometry_key(k) + (side, m)  # same key, same blocked table
            rename = self.kin.n_positions ** 2 >= RENAME_MIN_ENTRIES
            built = self._guard_by_geometry.get(shared) if rename else None
            if built is not None:  # the same function on other variables: a renaming
                g = self.ctx.bdd.let(self._bit_renaming(built[0], names), built[1])
            elif self.guards_from is not None:  # copied (~3 ms): cheaper than from the table
                src = self.guards_from
                g = src.ctx.bdd.copy(src.pair_guard(p, m, k, q, side), self.ctx.bdd)
            else:  # from the table (~10-40 ms at 36 x 19 positions)
                b = blocked_table(self.problem, k, side)[m]  # [i_p, j_q] over flat positions
                shape = self._shape()
                g = table_bdd(self.ctx, ~b.reshape(shape + shape), names)
            if rename:
                self._guard_by_geometry.setdefault(shared, (names, g))
            self._pair_guard[key] = g
        return g

    def _bit_renaming(self, old: list[str], new: list[str]) -> dict[str, str]:
        """Bit ``i`` of ``old[j]`` → bit ``i`` of ``new[j]`` (the variables have equal widths)."""
        out = {}
        for a, b in zip(old, new):
            bits_a, bits_b = self.ctx.bits([a]), self.ctx.bits([b])
            if len(bits_a) != len(bits_b):
                raise ModelError(f"cannot rename {a} to {b}: widths differ", value=(a, b))
            out.update(zip(bits_a, bits_b))
        return out

    def unary_guard(self, p: int, m: int, k: int, q: int, side: int, cq: int) -> BDD:
        """``¬B_{p,m}(x_p, c_q)``: the guard against a neighbour frozen at flat position ``cq``."""
        key = (p, m, q, cq)
        g = self._unary_guard.get(key)
        if g is None:
            self.declare(p)
            b = blocked_column(self.problem, k, side, m, cq)
            g = table_bdd(self.ctx, ~b.reshape(self._shape()), var_names(self.problem, p))
            self._unary_guard[key] = g
        return g

    def frozen_guard(self, p: int, m: int, outside: tuple[tuple[int, int, int], ...]) -> BDD:
        """``¬V_{p,m}(x_p) ∧ ⋀_q ¬B_{p,m}(x_p, c_q)`` over frozen neighbours ``(k, side, c_q)``,
        with ``V_p`` the moves ``p``'s own constraints refuse (obstacles, joint rules, held:
        :meth:`Problem.unary`): the rows OR-ed in numpy, then one BDD (cached per
        ``(p, m, outside)``).  The pair tables fold ``V_p`` in too, but a window without
        ``p``'s neighbours (the relaxed one, or a robot with none) must not lose it."""
        key = (p, m, outside)
        g = self._unary_guard.get(key)
        if g is None:
            self.declare(p)
            own = self.problem.unary().get(p)
            blocked = np.zeros(self.kin.n_positions, dtype=bool) if own is None else own[1][m].copy()
            for k, side, cq in outside:
                blocked |= blocked_column(self.problem, k, side, m, cq)
            g = table_bdd(self.ctx, ~blocked.reshape(self._shape()), var_names(self.problem, p))
            self._unary_guard[key] = g
        return g

    def state(self, members: Iterable[int], config: np.ndarray) -> BDD:
        """The cube of the members' positions in ``config`` (``(N, J)``)."""
        values = {}
        for p in members:
            self.declare(p)
            for name, v in zip(var_names(self.problem, p), config[p]):
                values[name] = int(v)
        return self.ctx.assignment(values)

    # -- the guarded system of a window -------------------------------------------
    def system(self, members: Sequence[int], frozen: np.ndarray | None = None, *,
               init: np.ndarray | None = None, target: np.ndarray | None = None,
               merged: bool = False) -> "GuardedSystem":
        """The guarded moves of ``members``; non-members are frozen at ``frozen`` (``(N, J)``),
        or removed when ``frozen`` is None (the relaxed subproblem).  ``init`` defaults to
        the start, ``target`` to the problem's target (both ``(N, J)``).  Guards are kept
        as a conjunctive partition (one BDD per neighbour inside, one for all frozen
        ones); with ``merged`` each event's step and guards are conjoined once into one
        relation ``T_σ`` and images are one AndAbstract each (measured 2-3x faster on
        windows of a few alpha-beta robots, where the relations stay small)."""
        problem, ctx = self.problem, self.ctx
        members = sorted(int(p) for p in members)
        for p in members:
            self.declare(p)
        inside = set(members)
        init = problem.start if init is None else init
        target = problem.target if target is None else target
        flat_frozen = None if frozen is None else self.kin.flat_index(frozen)
        moves: dict[str, GuardedMove] = {}
        variables: list[str] = []
        for p in members:
            names = var_names(problem, p)
            variables.extend(names)
            for m, (joint, delta) in enumerate(self.moves):
                guards = []
                outside = []
                for k, q, side in self.adj[p]:
                    if q in inside:
                        guards.append(self.pair_guard(p, m, k, q, side))  # ¬B(x_p, x_q)
                    elif flat_frozen is not None:
                        outside.append((k, side, int(flat_frozen[q])))
                unary = self.frozen_guard(p, m, tuple(outside))  # ⋀_q ¬B(x_p, c_q), one table
                guards.insert(0, unary & self.enabled_step(p, m))
                ev = event_name(self.kin, p, joint, delta)
                moves[ev] = GuardedMove(ev, (p, joint, delta), names[joint], self.step_relation(p, m), guards)
        inv = ctx.domain(variables)
        level = {v: ctx.bdd.level_of_var(ctx.vars[v].bits[0]) for v in variables}
        variables.sort(key=level.__getitem__)
        return GuardedSystem(self, members, tuple(variables), moves, self.state(members, init) & inv,
                             self.state(members, target) & inv, inv, merged)

    def displaced_at_most(self, members: Sequence[int], config: np.ndarray, bound: int) -> BDD:
        """``|{q ∈ members : x_q ≠ config_q}| ≤ bound``: at most ``bound`` of ``members``
        away from their positions in ``config`` (a threshold function, built by counting
        member by member: ``f_j`` = exactly ``j`` displaced so far)."""
        ctx = self.ctx
        counts = [ctx.true] + [ctx.false] * bound
        for q in members:
            away = ~self.state([q], config)
            counts = [counts[0] & ~away] + [(counts[j] & ~away) | (counts[j - 1] & away) for j in range(1, bound + 1)]
        out = ctx.false
        for f in counts:
            out |= f
        return out

    def enabled_step(self, p: int, m: int) -> BDD:
        """``∃x'. step``: the positions from which the move exists (not past a hard stop)."""
        return self.ctx.exist([var_names(self.problem, p)[self.moves[m][0]]], self.step_relation(p, m), primed=True)

    def generator(self, members: Sequence[int], frozen: np.ndarray | None = None, *,
                  init: np.ndarray | None = None, target: np.ndarray | None = None,
                  name: str = "G") -> SymbolicGenerator:
        """:meth:`system` as a :class:`SymbolicGenerator` (each event's guards conjoined)."""
        return self.system(members, frozen, init=init, target=target).to_generator(name)

    def position_cube(self, p: int, position: Any) -> BDD:
        """The cube ``x_p = position``."""
        self.declare(p)
        return self.ctx.assignment({n: int(v) for n, v in zip(var_names(self.problem, p), position)})

    def decode(self, values: dict[str, int], members: Sequence[int], into: np.ndarray) -> np.ndarray:
        """Write the members' positions of a decoded state into a copy of ``into``."""
        out = into.copy()
        for p in members:
            for j, name in enumerate(var_names(self.problem, p)):
                out[p, j] = values[name]
        return out


@dataclass
class GuardedMove:
    """One controllable move: ``R(x, x'_var) = step(x_var, x'_var) ∧ ⋀ guards(x)``."""

    event: str
    move: tuple[int, int, int]
    var: str
    step: BDD
    guards: list[BDD]


@dataclass
class GuardedSystem:
    """The guarded moves of a window with partitioned guards; images never conjoin them
    into one relation: ``Pre_σ(X) = (∃x'_v. step_σ ∧ X[x_v := x'_v]) ∧ g_1 ∧ … ∧ g_r`` (the
    guards read no primed bit)."""

    model: CoordinationModel
    members: list[int]
    variables: tuple[str, ...]
    moves: dict[str, GuardedMove]
    init: BDD
    marked: BDD
    invariant: BDD
    merged: bool = False
    _relations: dict[str, list[BDD]] = field(default_factory=dict, repr=False)
    #: event → the first conjunct of its relation ∧ invariant (this system's own: see :meth:`pre`)
    _entry: dict[str, BDD] = field(default_factory=dict, repr=False)

    def relation(self, event: str) -> list[BDD]:
        """``T_σ = step_σ ∧ ⋀ guards_σ`` as few conjuncts: the guards are conjoined in
        turn into the current cluster while it stays under :data:`CLUSTER_NODES` nodes
        (clustering of a partitioned relation; a positioner with six neighbours in the
        middle of the order would otherwise get a relation exponential in the cut)."""
        rel = self._relations.get(event)
        if rel is None:
            mv = self.moves[event]
            rel = [mv.step]
            for g in mv.guards:
                if len(g) > CLUSTER_NODES or len(rel[-1]) > CLUSTER_NODES:
                    rel.append(g)  # a conjunct this big would only be computed to be thrown away
                    continue
                merged = rel[-1] & g
                if len(merged) <= CLUSTER_NODES:
                    rel[-1] = merged
                else:
                    rel.append(g)
            self._relations[event] = rel
        return rel

    def restricted(self, region: BDD) -> "GuardedSystem":
        """The same moves inside ``invariant ∧ region``: a subgraph of the configuration graph
        (every path of it is a path of ``self``; the converse does not hold, so a search of it
        that fails proves nothing).  Relations are shared."""
        return replace(self, init=self.init & region, marked=self.marked & region,
                       invariant=self.invariant & region, _relations=self._relations, _entry={})

    def prime(self, x: BDD, var: str) -> BDD:
        """``X[x_v := x'_v] = ∃x_v. X ∧ I_v`` with ``I_v = (x_v ↔ x'_v)``: an AndAbstract costs
        time in the size of ``X``, where ``dd``'s ``let`` loops over every declared variable
        (thousands in a whole-grid manager)."""
        model = self.model
        ident = model._identity.get(var)
        if ident is None:
            ident = model._identity[var] = model.ctx.identity([var])
        return model.ctx.and_exist(x, ident, model.ctx.bits([var]))

    def pre(self, x: BDD, event: str, primed: BDD | None = None) -> BDD:
        """``{q ∈ Inv : δ(q, σ) ∈ X}``; ``primed`` = ``X[x_v := x'_v]`` if known.

        The invariant ``Inv`` (unprimed) is conjoined into the relation's first conjunct
        once per system, ``∃x'_v. (T¹_σ ∧ Inv) ∧ X'``, so every later conjunction works on
        the states of ``Inv`` only.  Inside a :meth:`restricted` region (few members
        displaced) this made the images of SDSS-V's costliest 5-robot window at 36 × 19
        positions 1.3–1.6× faster (two runs) than conjoining ``Inv`` once after the union of the
        pre-images; the 127-robot run took 22.5–24.1 s against 27.4–30.3 s
        (``benchmarks/bench_window_order.py``, ``bench_resolution.py``)."""
        ctx = self.model.ctx
        mv = self.moves[event]
        xp = self.prime(x, mv.var) if primed is None else primed
        rest = self.relation(event)[1:] if self.merged else mv.guards  # (∃x'_v. T¹_σ ∧ X') ∧ T²_σ ∧ …
        entry = self._entry.get(event)
        if entry is None:
            first = self.relation(event)[0] if self.merged else mv.step
            entry = self._entry[event] = first & self.invariant
        out = ctx.and_exist(entry, xp, ctx.bits([mv.var], primed=True))
        for g in rest:
            if out == ctx.false:
                break
            out &= g
        return out

    def allowed(self, state: BDD, event: str) -> bool:
        """Is ``event`` allowed at the single state ``state`` (a cube)?"""
        ctx = self.model.ctx
        mv = self.moves[event]
        return all(state & g != ctx.false for g in mv.guards)

    def to_generator(self, name: str = "G") -> SymbolicGenerator:
        ctx = self.model.ctx
        events = {}
        for ev, mv in self.moves.items():
            rel = mv.step
            for g in mv.guards:
                rel &= g
            events[ev] = EventRelation(Event(ev, True), rel, (mv.var,))
        return SymbolicGenerator(ctx, name, self.variables, events, self.init, self.marked, self.invariant)
