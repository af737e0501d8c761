"""A positioner's every option and position against one step of a neighbour: merged motions in batches.

Plan improvement (:mod:`.improve`) asks, for a positioner ``r`` and a neighbour ``q`` doing
option ``v`` from position ``j0`` during some step (its actual move in the plan)::

    hit[u, i] = r doing option u from position i while q does v from j0 collides

for every option ``u`` and position ``i`` of ``r`` at once.  Where one of the two stands
and the other turns one joint, the swept tables answer (those entries are left ``False``
here); the others are the pair's certified simultaneous motion,
:func:`~supcoord.geometry.motion.prefiltered_motion_collides` (end-point bounds first, then
the certified sampling).  A move past a hard stop counts as colliding.  The tables are
cached per pair geometry and ``(v, j0)``; :meth:`MergedMotions.compute` decides several
``(v, j0)`` of one pair in one call, because the certified motions are many small numpy
operations whose cost is mostly per call: every entry is decided on its own, so a batch
gives the same Booleans as one call per key.
"""

from __future__ import annotations

import numpy as np

from ..geometry.motion import prefiltered_motion_collides
from ..problems.problem import Problem

__all__ = ["MergedMotions"]


class MergedMotions:
    """The ``hit[u, i]`` tables of the module docstring for the pairs of ``problem``.

    ``pos``: the lattice positions; ``deltas``: the options of a step (0 stands, then the
    single-joint moves up to ``n_single``, then several joints at once); ``nxt[u, i]``: the
    position after option ``u`` from ``i`` (−1 past a hard stop); ``cache``: where the
    tables are kept, keyed by the pair's geometry, ``v`` and ``j0``."""

    def __init__(self, problem: Problem, pos: np.ndarray, deltas: list[np.ndarray], n_single: int,
                 nxt: np.ndarray, cache: dict[tuple, np.ndarray]):
        self.problem, self.pos, self.n_single, self.nxt, self.cache = problem, pos, n_single, nxt, cache
        self.deltas = np.asarray(deltas)
        self._geometry: dict[tuple[int, int], tuple] = {}  # (pair, side) -> the geometry key of (r, q)
        self._entries: dict[int, tuple[np.ndarray, ...]] = {}  # see entries()

    def key(self, k: int, side: int, v: int, j0: int) -> tuple:
        """The cache key: the geometry of pair ``k`` seen from ``side`` (``r``'s), then ``(v, j0)``."""
        geometry = self._geometry.get((k, side))
        if geometry is None:
            a, b = (int(x) for x in self.problem.pairs[k])
            geometry = self._geometry[k, side] = self.problem.geometry_key(a, b) if side == 0 else \
                self.problem.geometry_key(b, a)
        return geometry + (v, j0)

    def known(self, k: int, side: int, v: int, j0: int) -> bool:
        return self.key(k, side, v, j0) in self.cache

    def hits(self, k: int, side: int, v: int, j0: int) -> np.ndarray:
        """``hit[u, i]`` (module docstring), computed on first use."""
        key = self.key(k, side, v, j0)
        hit = self.cache.get(key)  # keyed by the pair's geometry: a grid has few distinct offsets
        if hit is None:
            self.compute(k, side, [(v, j0)])
            hit = self.cache[key]
        return hit

    def entries(self, v: int) -> tuple[np.ndarray, ...]:
        """``(uu, ii, sel, uu[sel], ii[sel])``: the entries ``(u, i)`` of a table for the
        neighbour's option ``v`` that are not the swept tables' (option-major), and which of
        them stay on the lattice (``nxt[u, i] ≥ 0``); the same for every ``v`` of one kind
        (standing, one joint, several)."""
        kind = 0 if v == 0 else (1 if v < self.n_single else 2)
        out = self._entries.get(kind)
        if out is None:
            wanted = [u for u in range(len(self.deltas))
                      if not ((u == 0 and v < self.n_single) or (v == 0 and u < self.n_single))]
            uu, ii = (x.ravel() for x in np.meshgrid(wanted, np.arange(len(self.pos)), indexing="ij"))
            sel = np.nonzero(self.nxt[uu, ii] >= 0)[0]
            out = self._entries[kind] = (uu, ii, sel, uu[sel], ii[sel])
        return out

    def compute(self, k: int, side: int, keys: list[tuple[int, int]]) -> None:
        """The tables of pair ``k`` (``r`` on ``side``) for each ``(v, j0)`` in ``keys``, in one batch."""
        problem, pos, nxt, n_single = self.problem, self.pos, self.nxt, self.n_single
        a, b = (int(x) for x in problem.pairs[k])
        r, q = (a, b) if side == 0 else (b, a)
        parts = [self.entries(v) for v, _ in keys]
        uu_s = np.concatenate([part[3] for part in parts])
        ii_s = np.concatenate([part[4] for part in parts])
        v_s = np.concatenate([np.full(len(part[2]), v) for (v, _), part in zip(keys, parts)])
        j_s = np.concatenate([np.full(len(part[2]), j0) for (_, j0), part in zip(keys, parts)])
        dist = problem.tables().distance_view(k)
        dist = dist if side == 0 else dist.T  # [position of r, position of q]
        out = prefiltered_motion_collides(
            problem.kin(r), problem.bases[r], pos, ii_s, nxt[uu_s, ii_s], self.deltas[uu_s],
            problem.kin(q), problem.bases[q], j_s, nxt[v_s, j_s], self.deltas[v_s],
            float(problem.buffers[r] + problem.buffers[q]), dist)
        lo = 0
        for (v, j0), (uu, ii, sel, _, _) in zip(keys, parts):
            entries = np.ones(len(uu), dtype=bool)  # past a hard stop: not allowed
            entries[sel] = out[lo:lo + len(sel)]
            lo += len(sel)
            hit = np.zeros((len(self.deltas), len(pos)), dtype=bool)
            hit[uu, ii] = entries
            self.cache[self.key(k, side, v, j0)] = hit
