"""The coupled reading of the paper's model: collision and free events driven by geometry.

In the literal model (:mod:`.literal`) the positioners share no events and ``k``/``e``
fire whenever ``G^P`` allows, so nothing couples them.  Here each positioner ``i`` keeps
the paper's state ``(pos_i, lvl_i)`` (``lvl`` = how many neighbours it has registered in
its safety zone, 0–2) but the uncontrollable events are *due* exactly when the
neighbours' positions say so.  With arms as segments on a hex layout (:class:`Geometry`),
``Z_ij(p, q)``: the arms of ``i`` at ``p`` and ``j`` at ``q`` are closer than ``zone`` mm;
``c_i = |{j ∈ N(i) : Z_ij(pos_i, pos_j)}|``; ``X^±_ij(p, q)``: the one-step move of ``i``
from ``p`` to ``p ± 1`` passes closer than ``2·buffer`` mm to ``j``'s arm at ``q`` (a hard
collision, swept motion sampled)::

    k_i : lvl_i < min(c_i, 2)                          → lvl_i + 1   (uncontrollable)
    e_i : lvl_i ≥ 1 ∧ c_i = 0                          → lvl_i := 0  (uncontrollable)
    v_i : lvl_i = 0 ∧ ∀j ¬X^+_ij                      → pos_i + 1
    w_i : lvl_i = 0 ∧ ∀j ¬X^-_ij                      → pos_i − 1
    h_i : lvl_i ≥ 1 ∧ c_i ≥ 1 ∧ (∀j ∈ zone. r_i < r_j) ∧ ∀j ¬X^+_ij → pos_i + 1, lvl_i := 0
    l_i : lvl_i ≥ 1 ∧ c_i ≥ 1 ∧ (∀j ∈ zone. r_i > r_j) ∧ ∀j ¬X^-_ij → pos_i − 1, lvl_i := 0
    m_i : lvl_i = 2 ∧ c_i ≤ 1                          → lvl_i := 1

(``r`` the priority, smaller = higher).  So a neighbour entering the zone makes ``k``
pending (and under preemptive forcibility a pending event preempts), ``e`` fires exactly
when the zone empties, the positioner that outranks everyone in its zone escapes
clockwise (``h``), the one outranked by everyone counter-clockwise (``l``), a medium one
waits and acknowledges a departure (``m``): the paper's prose, with the priority class
read from the neighbours actually in the zone.  Moves into a hard collision are not in
the plant; every position-changing event is controllable, so this equals a safety
specification forbidding them.  The specification ``S^P`` counts ``h``/``l`` as forward /
backward steps too and lets a positioner leave its target (docs/paper.md).

Each event relation writes only its own positioner's variables and reads the
neighbours' current positions; the plant is ``sync`` of these open components.  The
positioners' blocks of variables are declared in a bandwidth-reducing order of the
neighbour graph (:func:`positioner_order`), so that each relation spans few levels and
saturation gets one event cluster per neighbourhood (docs/paper.md §7).

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (the seed paper; Remark on preemption, Definitions "Collision/Free Events" and "Priority
  Events").
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..bdd.context import BDD, Context
from ..bdd.ordering import bandwidth, cuthill_mckee
from ..des import explicit_ops as XO
from ..des import symbolic_ops as SO
from ..des.generator import Generator
from ..des.symbolic import EventRelation, SymbolicGenerator
from ..errors import InputError
from ..geometry.collision import colliding_pairs, placed_segments, segment_distance
from ..geometry.kinematics import Rotary
from .events import KINDS, positioner_events
from .literal import PaperInstance, hex_sites, ring_step, spec_explicit, spec_symbolic

__all__ = ["Geometry", "CoupledModel", "ORDERS", "positioner_order", "coupled_models", "coupled_models_explicit"]

#: how :func:`coupled_models` lays the positioners' blocks of variables out
ORDERS = ("auto", "layout", "bandwidth")


@dataclass(frozen=True)
class Geometry:
    """Rotary arms on a hex grid (mm): pitch, arm length, collision buffer around each arm
    (hard collision below ``2·buffer``) and the safety-zone distance (``zone > 2·buffer``)."""

    pitch: float = 22.4
    arm: float = 15.0
    buffer: float = 2.0
    zone: float = 8.0
    samples: int = 16

    def __post_init__(self) -> None:
        for name in ("pitch", "arm", "buffer", "zone"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0):
                raise InputError(f"geometry.{name} must be a positive number, got {v!r}", value=v, where=name)
        if self.zone <= 2 * self.buffer:
            raise InputError(f"the safety zone ({self.zone} mm) must exceed the collision distance 2·buffer "
                             f"({2 * self.buffer} mm)", value=self.zone, where="zone")


class CoupledModel:
    """Geometry tables of an instance: neighbour pairs, zone and swept-collision tables."""

    def __init__(self, inst: PaperInstance, geometry: Geometry | None = None, bases: np.ndarray | None = None):
        if not isinstance(inst, PaperInstance):
            raise InputError(f"CoupledModel needs a PaperInstance (paper_example, random_instance), got "
                             f"{type(inst).__name__}", value=inst)
        if geometry is not None and not isinstance(geometry, Geometry):
            raise InputError(f"geometry must be a Geometry, got {type(geometry).__name__}", value=geometry)
        self.inst = inst
        self.geo = geometry or Geometry()
        self.bases = hex_sites(inst.size, self.geo.pitch) if bases is None else np.asarray(bases, float)
        self.kin = Rotary(self.geo.arm, inst.steps)  # docs/formats.md: θ = −2πk/steps (v turns clockwise)
        ring = np.arange(inst.steps)[:, None]
        self._next = {d: self.kin.step_array(ring, 0, d)[0][:, 0].tolist() for d in (1, -1)}  # pos ± 1 (wrapping)
        reach = 2 * self.geo.arm + self.geo.zone
        self.neighbours: list[list[int]] = [[] for _ in range(inst.size)]
        self.zone: dict[tuple[int, int], np.ndarray] = {}
        self.swept: dict[tuple[int, int, int], np.ndarray] = {}  # (i, j, ±1) -> [p, q]: i moves p→p±1, j at q
        cache: dict[tuple[float, float], tuple] = {}
        for i, j in itertools.combinations(range(inst.size), 2):
            off = self.bases[j] - self.bases[i]
            if np.hypot(*off) >= reach:
                continue
            key = (round(float(off[0]), 6), round(float(off[1]), 6))
            if key not in cache:
                cache[key] = self._tables(off)
            zone, fi, bi, fj, bj = cache[key]
            self.neighbours[i].append(j)
            self.neighbours[j].append(i)
            self.zone[(i, j)], self.zone[(j, i)] = zone, zone.T
            self.swept[(i, j, 1)], self.swept[(i, j, -1)] = fi, bi
            self.swept[(j, i, 1)], self.swept[(j, i, -1)] = fj, bj

    def _tables(self, off: np.ndarray):
        g, kin = self.geo, self.kin
        o = np.zeros(2)
        pos = np.arange(self.inst.steps, dtype=float)[:, None]
        a = placed_segments(kin, o, pos)[:, None]  # i at p (axis 0)
        b = placed_segments(kin, off, pos)[None, :]  # j at q (axis 1)
        zone = segment_distance(a[..., 0, :], a[..., 1, :], b[..., 0, :], b[..., 1, :]) < g.zone
        t = np.linspace(0.0, 1.0, g.samples + 1)

        def swept(base_m, base_s, sign):  # mover at p moving by sign, still arm at q
            m = placed_segments(kin, base_m, (pos + sign * t)[:, None, :, None])  # [p, 1, s, 2, 2]
            s = placed_segments(kin, base_s, pos[None, :, None])  # [1, q, 1, 2, 2]
            d = segment_distance(m[..., 0, :], m[..., 1, :], s[..., 0, :], s[..., 1, :])
            return (d < 2 * g.buffer).any(-1)

        return zone, swept(o, off, 1), swept(o, off, -1), swept(off, o, 1), swept(off, o, -1)

    # -- explicit rules (the reference twin) ----------------------------------------

    def count(self, i: int, pos: tuple[int, ...]) -> int:
        return sum(bool(self.zone[(i, j)][pos[i], pos[j]]) for j in self.neighbours[i])

    def in_zone(self, i: int, pos: tuple[int, ...]) -> list[int]:
        return [j for j in self.neighbours[i] if self.zone[(i, j)][pos[i], pos[j]]]

    def move_free(self, i: int, pos: tuple[int, ...], sign: int) -> bool:
        return not any(self.swept[(i, j, sign)][pos[i], pos[j]] for j in self.neighbours[i])

    def hard_collisions(self, pos: tuple[int, ...]) -> list[tuple[int, int]]:
        """Pairs whose arms are closer than ``2·buffer`` in configuration ``pos``."""
        pairs = [(i, j) for i in range(self.inst.size) for j in self.neighbours[i] if i < j]
        return [(i, j) for i, j, _ in colliding_pairs(self.kin, self.bases, self.geo.buffer, np.array(pos)[:, None],
                                                       pairs)]

    def fibre(self, i: int, q: int) -> np.ndarray:
        """The fibre (arm tip) of positioner ``i`` at position ``q`` in the focal plane (mm)."""
        return placed_segments(self.kin, self.bases[i], [q])[1]

    def successors(self, i: int, pos: tuple[int, ...], lvl: tuple[int, ...]) -> dict[str, tuple[int, int]]:
        """``{kind: (pos_i', lvl_i')}`` for the events of positioner ``i`` defined here."""
        L, p, nxt = lvl[i], pos[i], self._next
        zone = self.in_zone(i, pos)
        c = len(zone)
        out: dict[str, tuple[int, int]] = {}
        if L < min(c, 2):
            out["k"] = (p, L + 1)
        if L >= 1 and c == 0:
            out["e"] = (p, 0)
        if L == 0:
            if self.move_free(i, pos, 1):
                out["v"] = nxt[1][p], 0
            if self.move_free(i, pos, -1):
                out["w"] = nxt[-1][p], 0
        if L >= 1 and c >= 1:
            r = self.inst.priority
            if all(r[i] < r[j] for j in zone) and self.move_free(i, pos, 1):
                out["h"] = nxt[1][p], 0
            if all(r[i] > r[j] for j in zone) and self.move_free(i, pos, -1):
                out["l"] = nxt[-1][p], 0
        if L == 2 and c <= 1:
            out["m"] = (p, 1)
        return out

    # -- symbolic guards -----------------------------------------------------------

    def _table_bdd(self, ctx: Context, i: int, j: int, table: np.ndarray) -> BDD:
        """``{(pos_i, pos_j) : table[pos_i, pos_j]}``."""
        pi, pj = f"pos{i + 1}", f"pos{j + 1}"
        u = ctx.false
        for p in range(table.shape[0]):
            qs = np.nonzero(table[p])[0]
            if len(qs) == 0:
                continue
            row = ctx.false
            for q in qs:
                row |= ctx.eq(pj, int(q))
            u |= ctx.eq(pi, p) & row
        return u

    def plant_symbolic(self, ctx: Context, i: int) -> SymbolicGenerator:
        """The open component of positioner ``i``: writes ``pos_i``, ``lvl_i``; reads neighbours."""
        inst, n = self.inst, self.inst.steps
        num = i + 1
        pos, lvl = f"pos{num}", f"lvl{num}"
        Z = {j: self._table_bdd(ctx, i, j, self.zone[(i, j)]) for j in self.neighbours[i]}
        free = {s: ctx.true for s in (1, -1)}
        for j in self.neighbours[i]:
            for s in (1, -1):
                free[s] &= ~self._table_bdd(ctx, i, j, self.swept[(i, j, s)])
        c1 = ctx.false  # c_i ≥ 1
        for j in Z:
            c1 |= Z[j]
        c2 = ctx.false  # c_i ≥ 2
        for a, b in itertools.combinations(Z, 2):
            c2 |= Z[a] & Z[b]
        r = inst.priority
        top, bottom = c1, c1  # everyone in the zone is outranked by i / outranks i
        for j in Z:
            if not r[i] < r[j]:
                top &= ~Z[j]
            if not r[i] > r[j]:
                bottom &= ~Z[j]
        L = [ctx.eq(lvl, k) for k in range(3)]
        Lp = [ctx.eq(lvl, k, primed=True) for k in range(3)]
        fwd, bwd = ring_step(ctx, pos, n, 1), ring_step(ctx, pos, n, -1)
        busy = L[1] | L[2]
        rel = {
            "v": (L[0] & free[1] & fwd, (pos,)),
            "w": (L[0] & free[-1] & bwd, (pos,)),
            "k": ((L[0] & c1 & Lp[1]) | (L[1] & c2 & Lp[2]), (lvl,)),
            "e": (busy & ~c1 & Lp[0], (lvl,)),
            "h": (busy & top & free[1] & fwd & Lp[0], (pos, lvl)),
            "l": (busy & bottom & free[-1] & bwd & Lp[0], (pos, lvl)),
            "m": (L[2] & ~c2 & Lp[1], (lvl,)),
        }
        ev = positioner_events(num)
        events = {ev[k].name: EventRelation(ev[k], rel[k][0], rel[k][1]) for k in KINDS}
        return SymbolicGenerator(
            ctx, f"G{num}", (pos, lvl), events, ctx.assignment({pos: inst.start[i], lvl: 0}),
            ctx.assignment({pos: inst.target[i], lvl: 0}), ctx.domain([pos, lvl]),
        )

    @cached_property
    def start_collisions(self) -> list[tuple[int, int]]:
        return self.hard_collisions(self.inst.start)

    @cached_property
    def target_collisions(self) -> list[tuple[int, int]]:
        return self.hard_collisions(self.inst.target)

    def check(self) -> None:
        """Raise :class:`InputError` if the start or the target configuration itself collides."""
        for what, pairs in (("start", self.start_collisions), ("target", self.target_collisions)):
            if pairs:
                i, j = pairs[0]
                raise InputError(f"the {what} configuration collides: P{i + 1} and P{j + 1} are closer than "
                                 f"{2 * self.geo.buffer} mm", value=[i + 1, j + 1], where=what)


def positioner_order(model: CoupledModel, order: str = "auto") -> list[int]:
    """The order of the positioners' variable blocks (``pos_i, lvl_i, cnt_i``) in the BDD.

    - ``"layout"``: hex-grid order (centre, then ring by ring);
    - ``"bandwidth"``: the Cuthill–McKee order of the neighbour graph ``model.neighbours``
      (:func:`~supcoord.bdd.ordering.cuthill_mckee`), which keeps every positioner's
      block close to its neighbours' blocks (small bandwidth ``max |π(i) − π(j)|`` over
      neighbour pairs);
    - ``"auto"`` (default): ``"bandwidth"`` where it has a smaller bandwidth than the
      layout order, else ``"layout"`` (two or three mutual neighbours: every order has
      the same bandwidth, and the layout order keeps the BDDs the demo documents).

    Why it matters (docs/paper.md §7, measured): every event of positioner ``i`` reads its
    neighbours' positions, so the highest BDD level it touches, ``Top(σ)``, is that of its
    uppermost neighbour.  In layout order the centre comes first and neighbours every
    positioner of the first ring, so every event has the same ``Top`` and saturation has
    one cluster: it degenerates into chaining over all events.  Beyond the first ring the
    layout order (a spiral) also puts neighbours of the outer rings far apart: the
    collision-free configurations of 19 positioners take 941,126 nodes in layout order
    and 17,500 in Cuthill–McKee order.  The order changes no result, only BDD sizes.
    """
    if order not in ORDERS:
        raise InputError(f"unknown positioner order {order!r} (use one of {', '.join(ORDERS)})", value=order,
                         where="order")
    layout = list(range(model.inst.size))
    if order == "layout":
        return layout
    cm = [i for part in cuthill_mckee(model.neighbours) for i in part]
    if order == "bandwidth" or bandwidth(model.neighbours, cm) < bandwidth(model.neighbours, layout):
        return cm
    return layout


def coupled_models(model: CoupledModel, ctx: Context | None = None, *,
                   order: str = "auto") -> tuple[SymbolicGenerator, SymbolicGenerator]:
    """``(G, allevents(G) || S)`` of the coupled reading; variables ``pos_i, lvl_i, cnt_i``
    interleaved per positioner, the positioners in :func:`positioner_order` (``order``)."""
    ctx = ctx or Context()
    inst = model.inst
    for i in positioner_order(model, order):  # declare first: guards read neighbours' bits
        num = i + 1
        ctx.add_variable(f"pos{num}", inst.steps)
        ctx.add_variable(f"lvl{num}", 3)
        ctx.add_variable(f"cnt{num}", inst.steps)
    plants = [model.plant_symbolic(ctx, i) for i in range(inst.size)]
    specs = [spec_symbolic(ctx, i + 1, inst.steps, inst.start[i], inst.target[i], sees_priority=True, absorbing=False,
                           declare=False) for i in range(inst.size)]
    G = SO.sync(*plants, name="G")
    return G, SO.sync(SO.allevents(ctx, G), SO.sync(*specs, name="S"), name="ALLxS")


def plant_explicit(model: CoupledModel, max_states: int = 2_000_000) -> Generator:
    """The coupled plant explicitly (accessible part, breadth-first from the start)."""
    inst = model.inst
    N = inst.size
    evs = [positioner_events(i + 1) for i in range(N)]
    start = (tuple(inst.start), (0,) * N)
    index = {start: 0}
    queue = [start]
    trans = []
    for pos, lvl in queue:
        src = index[(pos, lvl)]
        for i in range(N):
            for kind, (p2, l2) in model.successors(i, pos, lvl).items():
                nxt = (pos[:i] + (p2,) + pos[i + 1:], lvl[:i] + (l2,) + lvl[i + 1:])
                if nxt not in index:
                    if len(queue) >= max_states:
                        raise InputError(f"the coupled plant has more than {max_states} states to enumerate", value=max_states)
                    index[nxt] = len(queue)
                    queue.append(nxt)
                trans.append((src, evs[i][kind].name, index[nxt]))
    marked = [index[s] for s in queue if s[0] == tuple(inst.target) and not any(s[1])]
    names = [",".join(f"P{i + 1}={p}" + ("" if l == 0 else f"^{l}") for i, (p, l) in enumerate(zip(*s))) for s in queue]
    alphabet = [e for d in evs for e in d.values()]
    return Generator(len(queue), alphabet, trans, 0, marked, "G", names)


def coupled_models_explicit(model: CoupledModel) -> tuple[Generator, Generator]:
    """The explicit twin of :func:`coupled_models`: ``(G, allevents(G) || S)``."""
    inst = model.inst
    G = plant_explicit(model)
    specs = [spec_explicit(i + 1, inst.steps, inst.start[i], inst.target[i], sees_priority=True, absorbing=False)
             for i in range(inst.size)]
    S = XO.sync(*specs, name="S") if len(specs) > 1 else specs[0]
    return G, XO.sync(XO.allevents(G), S, name="ALLxS")
