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


def random_configuration(kin: Kinematics, bases: Any, buffers: Any, rng: np.random.Generator,
                         allowed: np.ndarray | None = None, attempts: int = 100) -> np.ndarray:
    """A collision-free configuration ``(N, J)`` (module docstring).

    ``allowed`` (``(N, n_positions)`` bool) restricts each positioner's choices.
    """
    bases = np.asarray(bases, float)
    n = len(bases)
    buffers = np.broadcast_to(np.asarray(buffers, float), (n,))
    pairs = neighbour_pairs(bases, kin.reach, buffers)
    earlier: list[list[int]] = [[] for _ in range(n)]
    for a, b in pairs:
        earlier[int(b)].append(int(a))  # a < b: a is placed before b
    positions = kin.all_positions()
    local = kin.segments(positions)  # (C, 2, 2) relative to the base
    for _ in range(attempts):
        conf = np.zeros((n, kin.n_joints), dtype=int)
        seg = np.zeros((n, 2, 2))
        ok = True
        for p in range(n):
            free = np.ones(len(positions), dtype=bool) if allowed is None else allowed[p].copy()
            mine = local + bases[p]
            if earlier[p]:
                nb = np.array(earlier[p])
                d = segment_distance(mine[:, None, 0], mine[:, None, 1], seg[nb, 0], seg[nb, 1])  # (C, K)
                free &= np.all(d >= buffers[p] + buffers[nb], axis=1)
            choices = np.nonzero(free)[0]
            if len(choices) == 0:
                ok = False
                break
            k = int(rng.choice(choices))
            conf[p] = positions[k]
            seg[p] = placed_segments(kin, bases[p], positions[k])
        if ok:
            return conf
    raise InputError(f"could not draw a collision-free configuration in {attempts} attempts "
                     f"(the layout is too dense for these arms and buffers)", value=attempts)


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
