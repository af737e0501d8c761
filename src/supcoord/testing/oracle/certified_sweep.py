"""Certified swept checks: is ``min_{t ∈ [0,1]} d(t) < r``?  Branch and bound on ``t``.

Let ``d(t)`` be the distance between the colliding segments of two positioners while
they move (either or both, any joints at once) linearly in joint space,
``q + t·δ``.  No point of a segment moves faster than its arm's :meth:`.oracle_model.Arm.speed`
(``Σ_j |δ_j|·|radians per step_j|·lever_j``), so ``d`` is Lipschitz with ``L`` the sum of
the two speeds: ``|d(t) − d(t')| ≤ L·|t − t'|``.  Hence on an interval ``[t0, t1]`` of
width ``w``::

    min d  ≥  lb = (d(t0) + d(t1) − L·w) / 2          (the two cones meet)

The motion **collides** iff ``min_t d(t) < r`` (strictly; a distance of exactly ``r``
is free).  A computed distance carries rounding errors, so one within :data:`TIE`
(10⁻¹⁰ mm) of ``r`` is a *tie*: floating point, not geometry, would decide it.
Branch and bound, vectorised over many motions (*entries*):

- an entry **collides** as soon as a sample ``d(t_k) < r − TIE`` (a witness ``t_k``);
- an interval with ``lb ≥ r`` is settled free; an entry whose intervals are all
  settled is **free** (a proof);
- any other interval is bisected at its midpoint, sampled there, and both halves kept;
- an interval with ``L·w/2 ≤ 10⁻⁹`` mm (the bound can certify nothing finer), or an
  entry with more than :data:`MAX_OPEN` open intervals (a long stretch near distance
  ``r``), makes its entry **undecided** unless a collision is found: neither side is
  picked (:data:`UNDECIDED`).  Every iteration halves the widths, so the loop ends after
  at most ``log2(L/2·10⁻⁹) + 1`` rounds.

>>> import numpy as np
>>> gap = lambda e, t: np.abs(t - 0.5) + 1.0          # least distance 1 at t = 0.5
>>> certify(gap, np.array([1.0, 1.0]), np.array([1.0 - 1e-6, 1.0 + 1e-6])).tolist()   # [free, hit]
[0, 1]
>>> certify(gap, np.array([1.0]), np.array([1.0])).tolist()   # exactly r, certified: free
[0]
>>> touch = lambda e, t: 4 * (t - 0.3) ** 2 + 1.0     # a tangent at exactly r = 1: no bound settles it
>>> certify(touch, np.array([5.6]), np.array([1.0])).tolist()
[2]

References
----------
- R. Horst, H. Tuy, Global Optimization: Deterministic Approaches, Springer 1996
  (Lipschitz branch and bound, Piyavskii's cones).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["FREE", "HIT", "MAX_OPEN", "TIE", "TOLERANCE", "UNDECIDED", "certify", "classify"]

FREE, HIT, UNDECIDED = 0, 1, 2
#: the finest a bound may need to certify (mm)
TOLERANCE = 1e-9
#: computed distances within this of r are ties (mm): rounding, not geometry, would decide them
TIE = 1e-10
#: open intervals one entry may hold at once before it is declared undecided
MAX_OPEN = 4096

#: ``gap(entries, t)``: the distance ``d(t)`` of the given entries at the given times
Gap = Callable[[np.ndarray, np.ndarray], np.ndarray]


def certify(gap: Gap, lipschitz: np.ndarray, need: np.ndarray, d0: np.ndarray | None = None,
            d1: np.ndarray | None = None) -> np.ndarray:
    """Per entry ``FREE``, ``HIT`` or ``UNDECIDED`` (module docstring).

    ``lipschitz[e]``: ``L`` of entry ``e``; ``need[e]``: its ``r``; ``d0``/``d1``: ``d(0)``
    and ``d(1)`` when already known (static distances)."""
    lipschitz = np.asarray(lipschitz, dtype=float)
    need = np.asarray(need, dtype=float)
    n = len(lipschitz)
    every = np.arange(n)
    d0 = gap(every, np.zeros(n)) if d0 is None else np.asarray(d0, dtype=float)
    d1 = gap(every, np.ones(n)) if d1 is None else np.asarray(d1, dtype=float)
    hit = (d0 < need - TIE) | (d1 < need - TIE)
    undecided = np.zeros(n, dtype=bool)
    ent = np.nonzero(~hit & (need > 0))[0]  # no distance is below 0
    t0, t1, g0, g1 = np.zeros(len(ent)), np.ones(len(ent)), d0[ent], d1[ent]
    while len(ent):
        width = t1 - t0
        lb = (g0 + g1 - lipschitz[ent] * width) / 2
        keep = ~hit[ent] & (lb < need[ent])
        ent, t0, t1, g0, g1, width = ent[keep], t0[keep], t1[keep], g0[keep], g1[keep], width[keep]
        if not len(ent):
            break
        stuck = lipschitz[ent] * width / 2 <= TOLERANCE
        crowded = np.bincount(ent, minlength=n) > MAX_OPEN
        stuck |= crowded[ent]
        undecided[ent[stuck]] = True
        go = ~stuck
        ent, t0, t1, g0, g1 = ent[go], t0[go], t1[go], g0[go], g1[go]
        tm = (t0 + t1) / 2
        gm = gap(ent, tm) if len(ent) else np.zeros(0)
        hit[ent[gm < need[ent] - TIE]] = True
        ent = np.concatenate([ent, ent])
        t0, t1 = np.concatenate([t0, tm]), np.concatenate([tm, t1])
        g0, g1 = np.concatenate([g0, gm]), np.concatenate([gm, g1])
    out = np.full(n, FREE, dtype=np.uint8)
    out[undecided] = UNDECIDED
    out[hit] = HIT
    return out


def classify(least: np.ndarray, need: np.ndarray) -> np.ndarray:
    """``FREE``/``HIT``/``UNDECIDED`` of exactly computed least distances: a tie (within
    :data:`TIE` of ``r``) is undecided."""
    least, need = np.asarray(least, dtype=float), np.asarray(need, dtype=float)
    out = np.where(least < need - TIE, HIT, np.where(least >= need + TIE, FREE, UNDECIDED))
    return np.where(need > 0, out, FREE).astype(np.uint8)
