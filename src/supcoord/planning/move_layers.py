"""Backward move layers of a guarded system and the shortest witness read through them.

A witness is read forward through the layers (:func:`witness_moves`): at rank ``k``
some move leads into ``L(k−1)``; among those the tie-break prefers a joint that has not
moved since the current simultaneous step began, then the higher priority (smaller
number), then the event name — which interleaves positioners so that few simultaneous
steps hold them.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..bdd.context import BDD, ThrottledCheck
from ..errors import ModelError
from ..problems.plan import Move
from .guards import var_names
from .model import GuardedSystem

__all__ = ["MoveLayers", "move_layers", "witness_moves"]


@dataclass
class MoveLayers:
    """``layers[k] = L(k)`` of :func:`move_layers`; ``complete`` is False when stopped at the source."""

    layers: list[BDD]
    winning: BDD
    complete: bool
    stats: dict[str, Any]

    def rank(self, state: BDD) -> int | None:
        """Least ``k`` with ``state ⊆ W(k)``, None if none."""
        false = self.winning.bdd.false
        s = state
        for k, layer in enumerate(self.layers):
            s = s & ~layer
            if s == false:
                return k
        return None


def move_layers(S: GuardedSystem, target: BDD, stop_at: BDD | None = None, within: BDD | None = None) -> MoveLayers:
    """Backward breadth-first layers of a guarded system (all events controllable)::

        L(0) = T,   L(k+1) = Pre(L(k)) minus W(k),   W(k) = L(0) ∪ … ∪ L(k)

    With no uncontrollable event, ``Force(W) = {q : ∃c. δ(q,c) ∈ W} = Pre(W)`` under both
    semantics of :mod:`supcoord.synthesis.forcibility`, and ``Pre(W(k)) \\ W(k) =
    Pre(L(k)) \\ W(k)`` (a state with a successor in ``W(k−1)`` is already in ``W(k)``), so
    these are exactly the layers of :func:`~supcoord.synthesis.forcible_layers` (tested),
    computed on the frontier only with the guards kept partitioned
    (:meth:`GuardedSystem.pre`).  ``within`` (e.g. a supervisor's states) bounds the
    layers; the iteration stops once ``stop_at ⊆ W(k)``.
    """
    ctx = S.model.ctx
    inside = S.invariant if within is None else S.invariant & within
    t0 = time.perf_counter()
    check = ThrottledCheck(ctx)
    frontier = target & inside
    w = frontier
    layers = [frontier]
    complete = True
    k = 0
    wold = None
    while w != wold:
        check("layers", iteration=k, members=len(S.members))
        if stop_at is not None and (stop_at & ~w) == ctx.false:
            complete = False
            break
        wold = w
        pre = ctx.false
        for e in S.moves:
            pre |= S.pre(frontier, e)  # ⋃_σ Pre_σ(L(k))
        frontier = pre & inside & ~w  # L(k+1) = Pre(L(k)) minus W(k)
        if frontier != ctx.false:
            w = w | frontier
            layers.append(frontier)
            k += 1
    stats = {"iterations": k, "seconds": time.perf_counter() - t0}
    return MoveLayers(layers, w, complete, stats)


def witness_moves(S: GuardedSystem, lay: MoveLayers, init: np.ndarray) -> list[Move]:
    """A shortest move sequence from ``init`` (``(N, J)``, the system's initial state) to the
    target through the layers (tie-breaks in the module docstring)."""
    model = S.model
    ctx, kin = model.ctx, model.kin
    q = model.state(S.members, init)
    k = lay.rank(q)
    if k is None:
        raise ModelError("witness_moves: the initial state is not in the winning set", value=S.members)
    priority = model.problem.priority
    events = sorted(S.moves, key=lambda e: (priority[S.moves[e].move[0]], e))
    cfg = init.copy()
    open_step: set[tuple[int, int]] = set()
    out: list[Move] = []
    while k > 0:
        below = lay.layers[k - 1]
        best = None
        for e in events:
            p, joint, d = S.moves[e].move
            fresh = (p, joint) not in open_step
            if best is not None and not fresh:
                continue
            nxt = kin.step(cfg[p], joint, d)
            if nxt is None or not S.allowed(q, e):
                continue
            succ = ctx.exist(var_names(model.problem, p), q) & model.position_cube(p, nxt)
            if succ & below == ctx.false:  # δ(q, e) ∉ L(k−1)
                continue
            best = (fresh, (p, joint, d), succ, nxt)
            if fresh:
                break
        if best is None:
            raise ModelError(f"no move out of layer {k}: layers from another system?", value=k)
        fresh, mv, q, nxt = best
        if not fresh:
            open_step = set()
        open_step.add((mv[0], mv[1]))
        cfg[mv[0]] = nxt
        out.append(mv)
        k -= 1
    return out
