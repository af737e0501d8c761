"""The seed paper's positioner model, literally: ``G^P`` and ``S^P`` of each positioner.

Per positioner ``P`` with ``n`` discrete positions (Definition "Positioner", with the
typos resolved as in docs/paper.md §2: ``j`` runs over ``0..n-1`` and positions wrap)::

    Q_G = {q_j, q_j^1, q_j^2 : 0 ≤ j < n}     (free / one / two neighbours in the zone)
    v: q_j → q_{j+1}        w: q_{j+1} → q_j        (controllable, mod n)
    k: q_j → q_j^1 → q_j^2  e: q_j^1 → q_j          (uncontrollable)
    m: q_j^2 → q_j^1                                 (controllable)
    h: q_j^1, q_j^2 → q_{j+1}     l: q_{j+1}^1, q_{j+1}^2 → q_j      (controllable)
    q0 = q_start,  Qm = {q_target}

``Σ_G = {v, w, l, m, h, k, e}`` as the Definition says, but ``δ`` defines exactly one of
``l, m, h`` (Definition "Priority Events", read as in the paper's example: a *smaller*
priority number is a *higher* priority; the positioner that outranks all its colliding
neighbours gets ``h``, the one they all outrank gets ``l``, any other ``m``).

Specification (Definition "Specification", index ranges resolved): with
``n_v = (t − s) mod n`` forward and ``n_w = (s − t) mod n`` backward steps to the target,
``S^P`` has ``q_0``, a forward chain ``q_1 … q_{n_v−1}``, a backward chain
``q_{n_v} … q_{n_v+n_w−2}`` and ``q_m``; ``v`` walks the forward chain towards ``q_m``
and ``w`` back, ``w`` walks the backward chain towards ``q_m`` and ``v`` back; ``q_m``
has no outgoing transition (the text lists none).  That is the ring of positions
relative to the start with the target absorbing, which is how the symbolic twin
encodes it (a counter variable ``cnt ∈ [0, n)``, ``v: cnt ≠ t ∧ cnt' = cnt + 1``).
``Σ_S = {v, w}``: ``h`` and ``l`` move the positioner but ``S^P`` does not see them
(a defect of the text, kept here; the coupled variant fixes it).

Events are numbered as Table 1 (:mod:`.events`, whose names are re-exported here).

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, Supervisory coordination of robotic fiber
  positioners in multi-object spectrographs, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (the seed paper).
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer 2019.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..bdd.context import BDD, Context
from ..des import explicit_ops as XO
from ..des import symbolic_ops as SO
from ..des.generator import Generator
from ..des.symbolic import EventRelation, SymbolicGenerator
from ..errors import InputError
from ..progress import summary_html, summary_repr
from ..geometry.layout import hex_count, hex_grid

# Table 1's numbering lives in .events; its names stay importable from here
from .events import CONTROLLABLE, KINDS, OFFSETS, TABLE1, decode_label, event_label, positioner_events, priority_event  # noqa: F401

__all__ = [
    "KINDS",
    "TABLE1",
    "PaperInstance",
    "event_label",
    "decode_label",
    "positioner_events",
    "priority_event",
    "hex_sites",
    "hex_neighbours",
    "paper_example",
    "random_instance",
    "plant_explicit",
    "spec_explicit",
    "plant_symbolic",
    "spec_symbolic",
    "literal_models",
    "literal_models_explicit",
]

# -- instances -------------------------------------------------------------------


def hex_sites(count: int, pitch: float = 1.0) -> np.ndarray:
    """The first ``count`` bases of the hex grid in ``docs/formats.md`` order (centre, then ring
    by ring, each ring from +x counter-clockwise) as a ``(count, 2)`` array.

    >>> hex_sites(3, 2.0).round(3).tolist()
    [[0.0, 0.0], [2.0, 0.0], [1.0, 1.732]]
    """
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise InputError(f"need at least one positioner, got {count!r}", value=count)
    rings = 0
    while hex_count(rings) < count:
        rings += 1
    return hex_grid(rings, pitch)[:count]


def hex_neighbours(xy: np.ndarray, pitch: float = 1.0) -> tuple[tuple[int, ...], ...]:
    """Indices of the bases at distance ≈ ``pitch`` from each base (hex adjacency), in
    increasing order.  The bases are bucketed in cells a little larger than ``pitch``, so
    each base is compared with the bases of its own and the 8 adjacent cells only (linear
    in the number of bases, not quadratic)."""
    xy = np.asarray(xy, dtype=float)
    cell = 1.01 * pitch
    keys = np.floor(xy / cell).astype(np.int64) if len(xy) else np.zeros((0, 2), np.int64)
    buckets: dict[tuple[int, int], list[int]] = {}
    for i, (a, b) in enumerate(keys.tolist()):
        buckets.setdefault((a, b), []).append(i)
    out = []
    for i, (a, b) in enumerate(keys.tolist()):
        near = np.array(sorted(j for da in (-1, 0, 1) for db in (-1, 0, 1) for j in buckets.get((a + da, b + db), ())))
        d = np.hypot(*(xy[near] - xy[i]).T)
        out.append(tuple(int(j) for j in near[np.abs(d - pitch) < 1e-6 * pitch]))
    return tuple(out)


@dataclass(frozen=True)
class PaperInstance:
    """Positioners ``P_1 … P_N`` (index ``i`` is ``P_{i+1}``) with ``steps`` positions each,
    start and target positions, priorities (smaller = higher) and the neighbour lists of
    the layout that decide the static priority events of the literal model."""

    steps: int
    start: tuple[int, ...]
    target: tuple[int, ...]
    priority: tuple[int, ...]
    neighbours: tuple[tuple[int, ...], ...]

    def __post_init__(self) -> None:
        for name in ("start", "target", "priority", "neighbours"):
            if not isinstance(getattr(self, name), (list, tuple)):
                raise InputError(f"{name} must be a sequence with one entry per positioner, got "
                                 f"{type(getattr(self, name)).__name__}", value=getattr(self, name), where=name)
        n, N = self.steps, len(self.start)
        if isinstance(n, bool) or not isinstance(n, int) or n < 2:
            raise InputError(f"steps must be an integer >= 2, got {n!r}", value=n)
        if N < 1:
            raise InputError("an instance needs at least one positioner", value=N)
        for name in ("target", "priority", "neighbours"):
            if len(getattr(self, name)) != N:
                raise InputError(f"{name} has {len(getattr(self, name))} entries for {N} positioners", value=name)
        for name in ("start", "target"):
            for i, p in enumerate(getattr(self, name)):
                if isinstance(p, bool) or not isinstance(p, int) or not 0 <= p < n:
                    raise InputError(f"{name}[{i}] = {p!r} outside 0..{n - 1}", value=p, where=name)

    def summary(self) -> dict:
        """What a notebook shows: positioners, steps, start, target, priority (long ones cut)."""
        return {"positioners": len(self.start), "steps": self.steps, "start": self.start, "target": self.target,
                "priority": self.priority}

    def __repr__(self) -> str:
        return summary_repr("PaperInstance", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("PaperInstance", self.summary())

    @property
    def size(self) -> int:
        return len(self.start)

    def number(self, i: int) -> int:
        return i + 1

    def priority_kind(self, i: int) -> str:
        """The literal model's static priority event of positioner ``i``."""
        return priority_event(self.priority[i], [self.priority[j] for j in self.neighbours[i]])


#: most positioners and most positions per arm of a :func:`random_instance` (``supcoord paper``'s limits)
MAX_INSTANCE, MAX_INSTANCE_STEPS = 20_000, 4096


def paper_example(steps: int = 8, target: Sequence[int] = (1, 5, 5)) -> PaperInstance:
    """The paper's example: P1–P3 on the first three hex sites (mutual neighbours), starts
    ``[0], [6], [6]``, priorities 1, 2, 3 (P1 highest).  See docs/paper.md for ``steps``
    and ``target``."""
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 7 <= steps <= MAX_INSTANCE_STEPS:
        raise InputError(f"must be an integer in [7, {MAX_INSTANCE_STEPS}] (P2 and P3 start at position 6), "
                         f"got {steps!r:.60}", value=steps, where="steps")
    xy = hex_sites(3)
    return PaperInstance(steps, (0, 6, 6), tuple(int(t) for t in target), (1, 2, 3), hex_neighbours(xy))


def random_instance(count: int, steps: int, seed: int = 0) -> PaperInstance:
    """``count`` positioners on the hex grid, starts/targets uniform (seeded), start ≠ target,
    priorities = indices (P1 highest)."""
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not 1 <= count <= MAX_INSTANCE:
        raise InputError(f"must be an integer in [1, {MAX_INSTANCE}], got {count!r:.60}", value=count,
                         where="count")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 2 <= steps <= MAX_INSTANCE_STEPS:
        raise InputError(f"must be an integer in [2, {MAX_INSTANCE_STEPS}], got {steps!r:.60}", value=steps,
                         where="steps")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be an integer >= 0, got {seed!r}", value=seed, where="seed")
    rng = np.random.default_rng(seed)
    start = rng.integers(0, steps, count)
    target = (start + rng.integers(1, steps, count)) % steps
    return PaperInstance(
        steps, tuple(int(s) for s in start), tuple(int(t) for t in target), tuple(range(1, count + 1)),
        hex_neighbours(hex_sites(count)),
    )


# -- explicit generators -----------------------------------------------------------


def plant_explicit(number: int, steps: int, start: int, target: int, prio: str) -> Generator:
    """``G^P`` explicitly: state ``j`` is ``q_j``, ``n + j`` is ``q_j^1``, ``2n + j`` is ``q_j^2``."""
    n = steps
    if prio not in ("l", "m", "h"):
        raise InputError(f"priority event must be l, m or h, got {prio!r}", value=prio)
    ev = positioner_events(number)
    lb = {k: e.name for k, e in ev.items()}
    t: list[tuple[int, str, int]] = []
    for j in range(n):
        nxt = (j + 1) % n
        t += [(j, lb["v"], nxt), (nxt, lb["w"], j), (j, lb["k"], n + j), (n + j, lb["k"], 2 * n + j), (n + j, lb["e"], j)]
        if prio == "m":
            t.append((2 * n + j, lb["m"], n + j))
        elif prio == "h":
            t += [(n + j, lb["h"], nxt), (2 * n + j, lb["h"], nxt)]
        else:
            t += [(n + nxt, lb["l"], j), (2 * n + nxt, lb["l"], j)]
    names = [f"q{j}" for j in range(n)] + [f"q{j}^1" for j in range(n)] + [f"q{j}^2" for j in range(n)]
    return Generator(3 * n, ev.values(), t, start, [target], f"G{number}", names)


def spec_explicit(number: int, steps: int, start: int, target: int, *, sees_priority: bool = False,
                  absorbing: bool = True) -> Generator:
    """``S^P`` explicitly, numbered as the paper: ``q_0``, forward chain, backward chain, ``q_m``.

    ``sees_priority`` adds ``h`` (a forward step) and ``l`` (a backward step) to the
    counters; ``absorbing=False`` lets the positioner leave its target again (both used
    by the coupled reading, docs/paper.md).
    """
    n = steps
    ev = positioner_events(number)
    kinds = ["v", "w"] + (["l", "h"] if sees_priority else [])
    events = [ev[k] for k in kinds]
    fwd = ["v", "h"] if sees_priority else ["v"]
    bwd = ["w", "l"] if sees_priority else ["w"]
    nv = (target - start) % n
    if nv == 0:  # start = target: the chains are empty, q_0 = q_m
        if absorbing:
            return Generator(1, events, [], 0, [0], f"S{number}", ["q0=qm"])
        nv = n  # a full ring back to the target
    # the ring of positions relative to the start: offset d = 0 (q_0) … n-1, target at d = nv
    # paper numbering: q_0 = 0, forward chain q_1..q_{nv-1}, backward chain q_{nv}..q_{n-2}, q_m = n-1
    def idx(d: int) -> int:
        d %= n
        if d == 0:
            return 0
        if d == nv % n:
            return n - 1
        if d < nv:
            return d  # forward chain
        return nv + (n - d) - 1  # backward chain: d = n-1 is q_{nv}

    t = []
    for d in range(n):
        if absorbing and d == nv % n:
            continue
        for k in fwd:
            t.append((idx(d), ev[k].name, idx(d + 1)))
        for k in bwd:
            t.append((idx(d), ev[k].name, idx(d - 1)))
    if start == target:  # non-absorbing ring through the target q_0 = q_m
        names, marked = ["q0=qm"] + [f"q{j}" for j in range(1, n)], [0]
    else:
        names, marked = ["q0"] + [f"q{j}" for j in range(1, n - 1)] + ["qm"], [n - 1]
    return Generator(n, events, t, 0, marked, f"S{number}", names)


# -- symbolic generators -----------------------------------------------------------


def ring_step(ctx: Context, var: str, n: int, delta: int) -> BDD:
    """``{(x, x') : x' = x + delta mod n}`` for ``delta = ±1`` over one variable, as a
    ripple-carry increment (decrement) on the bits plus the wrap-around pair: O(bits)
    BDD operations.  ``x ∈ [0, n)`` is assumed (the invariant)."""
    v = ctx.vars[var]
    if delta not in (1, -1):
        raise InputError(f"ring_step moves by ±1, got {delta!r}", value=delta)
    bdd = ctx.bdd
    rel, carry = ctx.true, ctx.true  # ±1: the carry (borrow) into the lowest bit is 1
    for b, p in zip(reversed(v.bits), reversed(v.primed_bits)):  # least significant first
        x, xp = bdd.var(b), bdd.var(p)
        s = (x & ~carry) | (~x & carry)  # x_i xor c_i
        rel &= (xp & s) | (~xp & ~s)  # x'_i = x_i xor c_i
        carry = (x if delta == 1 else ~x) & carry  # carry of +1, borrow of -1
    last, first = (n - 1, 0) if delta == 1 else (0, n - 1)
    last = ctx.eq(var, last)
    return (~last & rel) | (last & ctx.eq(var, first, primed=True))


def _declare(ctx: Context, name: str, size: int, declare: bool) -> None:
    if declare:
        ctx.add_variable(name, size)
    elif name not in ctx.vars or ctx.vars[name].size != size:
        raise InputError(f"variable {name!r} of size {size} is not declared", value=name)


def plant_symbolic(ctx: Context, number: int, steps: int, start: int, target: int, prio: str, *,
                   declare: bool = True) -> SymbolicGenerator:
    """``G^P`` with a position variable ``pos{i}`` and a level variable ``lvl{i}`` (0, 1, 2)
    (declared here unless ``declare=False``)."""
    n = steps
    if prio not in ("l", "m", "h"):
        raise InputError(f"priority event must be l, m or h, got {prio!r}", value=prio)
    pos, lvl = f"pos{number}", f"lvl{number}"
    _declare(ctx, pos, n, declare)
    _declare(ctx, lvl, 3, declare)
    ev = positioner_events(number)
    fwd, bwd = ring_step(ctx, pos, n, 1), ring_step(ctx, pos, n, -1)
    L = [ctx.eq(lvl, i) for i in range(3)]
    Lp = [ctx.eq(lvl, i, primed=True) for i in range(3)]
    F = ctx.false
    rel = {
        "v": (L[0] & fwd, (pos,)),
        "w": (L[0] & bwd, (pos,)),
        "k": ((L[0] & Lp[1]) | (L[1] & Lp[2]), (lvl,)),
        "e": (L[1] & Lp[0], (lvl,)),
        "m": ((L[2] & Lp[1], (lvl,)) if prio == "m" else (F, ())),
        "h": (((L[1] | L[2]) & Lp[0] & fwd, (pos, lvl)) if prio == "h" else (F, ())),
        "l": (((L[1] | L[2]) & Lp[0] & bwd, (pos, lvl)) if prio == "l" else (F, ())),
    }
    events = {ev[k].name: EventRelation(ev[k], rel[k][0], rel[k][1]) for k in KINDS}
    return SymbolicGenerator(
        ctx, f"G{number}", (pos, lvl), events, ctx.assignment({pos: start, lvl: 0}), ctx.assignment({pos: target, lvl: 0}),
        ctx.domain([pos, lvl]),
    )


def spec_symbolic(ctx: Context, number: int, steps: int, start: int, target: int, *, sees_priority: bool = False,
                  absorbing: bool = True, declare: bool = True) -> SymbolicGenerator:
    """``S^P`` with a counter ``cnt{i}`` holding the position the specification believes in."""
    n = steps
    cnt = f"cnt{number}"
    _declare(ctx, cnt, n, declare)
    ev = positioner_events(number)
    guard = ~ctx.eq(cnt, target) if absorbing else ctx.true
    fwd, bwd = guard & ring_step(ctx, cnt, n, 1), guard & ring_step(ctx, cnt, n, -1)
    kinds = {"v": fwd, "w": bwd}
    if sees_priority:
        kinds.update(h=fwd, l=bwd)
    events = {ev[k].name: EventRelation(ev[k], r, (cnt,)) for k, r in kinds.items()}
    return SymbolicGenerator(
        ctx, f"S{number}", (cnt,), events, ctx.eq(cnt, start), ctx.eq(cnt, target), ctx.domain([cnt]),
    )


def literal_models(inst: PaperInstance, ctx: Context | None = None) -> tuple[SymbolicGenerator, SymbolicGenerator]:
    """``(G, allevents(G) || S)`` of the literal reading, symbolic; variables interleaved
    per positioner (``pos_i, lvl_i, cnt_i``) so every BDD stays linear in ``N``."""
    ctx = ctx or Context()
    plants, specs = [], []
    for i in range(inst.size):
        num = inst.number(i)
        plants.append(plant_symbolic(ctx, num, inst.steps, inst.start[i], inst.target[i], inst.priority_kind(i)))
        specs.append(spec_symbolic(ctx, num, inst.steps, inst.start[i], inst.target[i]))
    G = SO.sync(*plants, name="G")
    S = SO.sync(*specs, name="S")
    return G, SO.sync(SO.allevents(ctx, G), S, name="ALLxS")


def literal_models_explicit(inst: PaperInstance) -> tuple[Generator, Generator]:
    """The explicit twin of :func:`literal_models` (small instances only)."""
    plants = [plant_explicit(inst.number(i), inst.steps, inst.start[i], inst.target[i], inst.priority_kind(i))
              for i in range(inst.size)]
    specs = [spec_explicit(inst.number(i), inst.steps, inst.start[i], inst.target[i]) for i in range(inst.size)]
    G = XO.sync(*plants, name="G") if len(plants) > 1 else plants[0]
    S = XO.sync(*specs, name="S") if len(specs) > 1 else specs[0]
    return G, XO.sync(XO.allevents(G), S, name="ALLxS")
