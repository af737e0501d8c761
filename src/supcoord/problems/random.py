"""Seeded random coordination problems with collision-free starts and targets.

A random configuration is drawn positioner by positioner (layout order): positioner
``p`` takes a position uniformly from the positions compatible with the neighbours
placed before it::

    q_p ~ Uniform{ q ∈ Q : ∀ b < p neighbour of p.  dist(S_p(q), S_b(q_b)) ≥ r_p + r_b }

which is rejection sampling against the already placed neighbours, done exactly (the
compatible set is computed with numpy rather than by redrawing).  If some positioner
has no compatible position, the whole configuration is redrawn (up to
``attempts`` times).  Everything is a function of the seed
(``numpy.random.default_rng(seed)``), so a seed names a problem.

Targets are drawn the same way, independently of the start, or — with ``near = k`` —
among the positions within ``k`` steps per joint of the positioner's start (cyclic
where a joint wraps), which keeps the moves short for benchmarks.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError
from ..geometry.collision import neighbour_pairs, placed_segments, segment_distance
from ..geometry.kinematics import Kinematics, kinematics_from_spec
from ..geometry.layout import layout_from_spec
from .problem import Problem, parse_problem

__all__ = ["random_configuration", "random_problem"]


#: distances within this of a threshold (mm) are recomputed where the robots stand, as the
#: draw always computed them (a column's numbers come from the pair's offset, rounded)
BORDER = 1e-4
#: offsets are rounded to this (mm) to name a column of distances
_OFFSET_STEP = 1e-7
#: most distances kept by the columns of one draw (8 bytes each)
_COLUMN_ENTRIES = 2**24


class _Columns:
    """Distances from a robot's every position to one neighbour's segment, by the neighbour's
    offset (rounded to :data:`_OFFSET_STEP`) and position: the robots of a grid share a few
    offsets, so a draw of ``N`` robots computes a few hundred columns instead of ``N``.

    ``offsets`` ``(P, 2)`` are the pairs' offsets (mm) in the order :meth:`distances` is given them."""

    def __init__(self, local: np.ndarray, offsets: np.ndarray) -> None:
        self.local = local
        steps = np.round(offsets / _OFFSET_STEP).astype(np.int64).reshape(-1, 2)
        unique, self.offset_id = np.unique(steps, axis=0, return_inverse=True)
        self.offset_id = self.offset_id.reshape(-1)
        self.offsets = unique * _OFFSET_STEP
        self.rows: dict[int, int] = {}
        self.store = np.zeros((64, len(local)))

    def distances(self, pairs: np.ndarray, nb_positions: np.ndarray) -> np.ndarray:
        """``(C, K)``: from each position of a robot to the segments of its ``K`` neighbours
        (``pairs``: their rows of ``offsets``) at position numbers ``nb_positions`` (mm)."""
        c = len(self.local)
        if len(self.rows) * c > _COLUMN_ENTRIES:
            self.rows.clear()
        oid = self.offset_id[pairs]
        keys = (oid * c + nb_positions).tolist()
        todo = [i for i, key in enumerate(keys) if key not in self.rows]
        if todo:
            seg = self.local[nb_positions[todo]] + self.offsets[oid[todo]][:, None, :]
            d = segment_distance(self.local[:, None, 0], self.local[:, None, 1], seg[:, 0], seg[:, 1])
            first = len(self.rows)
            if first + len(todo) > len(self.store):
                self.store = np.concatenate([self.store, np.zeros((len(self.store) + len(todo), c))])
            for col, i in enumerate(todo):
                self.rows[keys[i]] = first + col
            self.store[first:first + len(todo)] = d.T
        return self.store[[self.rows[key] for key in keys]].T


def random_configuration(kin: Kinematics, bases: Any, buffers: Any, rng: np.random.Generator,
                         allowed: np.ndarray | None = None, attempts: int = 100) -> np.ndarray:
    """A collision-free configuration ``(N, J)`` (module docstring).

    ``allowed`` (``(N, n_positions)`` bool) restricts each positioner's choices.  The
    distances to the neighbours placed before come from columns shared between robots of
    equal offset (:class:`_Columns`); the few within :data:`BORDER` of their threshold are
    recomputed where the robots stand, so the draw is the one of the robots' own numbers.
    """
    bases = np.asarray(bases, float)
    n = len(bases)
    buffers = np.broadcast_to(np.asarray(buffers, float), (n,))
    pairs = neighbour_pairs(bases, kin.reach, buffers)
    pairs = pairs[np.argsort(pairs[:, 1], kind="stable")]  # a < b: a is placed before b
    split = np.searchsorted(pairs[:, 1], np.arange(n + 1))
    positions = kin.all_positions()
    local = kin.segments(positions)  # (C, 2, 2) relative to the base
    columns = _Columns(local, bases[pairs[:, 0]] - bases[pairs[:, 1]])
    for _ in range(attempts):
        conf = np.zeros((n, kin.n_joints), dtype=int)
        chosen = np.zeros(n, dtype=int)
        ok = True
        for p in range(n):
            free = np.ones(len(positions), dtype=bool) if allowed is None else allowed[p].copy()
            if split[p + 1] > split[p]:
                rows = np.arange(split[p], split[p + 1])
                nb = pairs[rows, 0]
                need = buffers[p] + buffers[nb]
                d = columns.distances(rows, chosen[nb])
                border = np.nonzero(np.abs(d - need) < BORDER)
                if len(border[0]):
                    d[border] = _exact(kin, local, bases, p, nb[border[1]], positions[chosen[nb[border[1]]]],
                                       border[0])
                free &= np.all(d >= need, axis=1)
            choices = np.nonzero(free)[0]
            if len(choices) == 0:
                ok = False
                break
            k = int(rng.choice(choices))
            chosen[p] = k
            conf[p] = positions[k]
        if ok:
            return conf
    raise InputError(f"could not draw a collision-free configuration in {attempts} attempts "
                     f"(the layout is too dense for these arms and buffers)", value=attempts)


def _exact(kin: Kinematics, local: np.ndarray, bases: np.ndarray, p: int, nb: np.ndarray, nb_positions: np.ndarray,
           mine: np.ndarray) -> np.ndarray:
    """Distances (mm) from robot ``p`` at position numbers ``mine`` to neighbours ``nb`` at
    ``nb_positions``, each segment placed at its own base."""
    a = local[mine] + bases[p]
    b = np.stack([placed_segments(kin, bases[q], pos) for q, pos in zip(nb, nb_positions)])
    return segment_distance(a[:, 0], a[:, 1], b[:, 0], b[:, 1])


def random_problem(layout: Any, kinematics: Any, buffer: float = 2.0, seed: int = 0, *,
                   near: int | None = None, priority: str = "random", attempts: int = 100,
                   start: Any = None, name: str | None = None, preset: str | None = None) -> Problem:
    """A random :class:`Problem` determined by ``seed``.

    ``layout``: a PROBLEM.json layout object (``{"kind": "hex", ...}``) or an ``(N, 2)``
    array of bases; ``kinematics``: a :class:`Kinematics` or its JSON object;
    ``priority``: ``"random"`` (a seeded permutation of ``1..N``) or ``"index"``
    (``1..N`` in layout order); ``start``: a fixed start ``(N, J)`` instead of a random
    one (e.g. a folded lattice); ``near``: targets within ``near`` steps per joint;
    ``name``/``preset``: recorded in the problem (PROBLEM.json's ``name`` and ``preset``).
    """
    kin = kinematics if isinstance(kinematics, Kinematics) else kinematics_from_spec(kinematics)
    if isinstance(layout, dict):
        layout_spec = dict(layout)
        bases = layout_from_spec(layout)
    else:
        bases = np.asarray(layout, float)
        layout_spec = {"kind": "points", "xy": bases.tolist()}
    n = len(bases)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**128:
        raise InputError(f"seed must be an integer in [0, 2^128), got {seed!r}", value=seed, where="seed")
    if priority not in ("random", "index"):
        raise InputError(f"priority must be 'random' or 'index', got {priority!r}", value=priority, where="priority")
    rng = np.random.default_rng(seed)
    if start is None:
        start_conf = random_configuration(kin, bases, buffer, rng, attempts=attempts)
    else:
        start_conf = np.asarray(start, dtype=int).reshape(n, kin.n_joints)
    allowed = None
    if near is not None:
        if near < 0:
            raise InputError(f"near must be >= 0, got {near}", value=near)
        positions = kin.all_positions()
        allowed = np.all(kin.joint_distance(positions[None, :, :], start_conf[:, None, :]) <= near, axis=-1)
    target = random_configuration(kin, bases, buffer, rng, allowed=allowed, attempts=attempts)
    if priority == "random":
        prio = (rng.permutation(n) + 1).tolist()
    elif priority == "index":
        prio = list(range(1, n + 1))
    else:
        raise InputError(f"priority must be 'random' or 'index', got {priority!r}", value=priority)
    data = {
        "layout": layout_spec,
        "kinematics": kin.to_json(),
        "collision": {"buffer": float(buffer)},
        "start": [kin.position_to_json(q) for q in start_conf],
        "target": [kin.position_to_json(q) for q in target],
        "priority": prio,
        "seed": int(seed),
    }
    if name:
        data["name"] = name
    if preset:
        data["preset"] = preset
    return parse_problem(data, where=name or f"random problem (seed {seed})")
