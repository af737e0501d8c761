"""Random tight problems for comparing the planner with the oracle (PROBLEM.json dicts).

``tight_problem(seed, kind, n)`` draws, from ``numpy.random.default_rng(seed)`` alone:

- the kinematics: rotary (``steps`` 6–24) or alpha-beta (``alpha_steps`` × ``beta_steps``
  from 4 × 2 to 12 × 7, ``beta_range`` ``[0, 180]`` or an asymmetric one), with random
  arm lengths, sized so that ``∏ positions ≤`` :data:`MAX_PRODUCT`;
- a layout of ``n`` bases (2–6) in one of three shapes — ``line``, ``hex`` (the first
  ``n`` bases of a hex grid) or ``cluster`` (each base near a random earlier one) — with
  neighbours ``f·reach`` apart, ``f`` drawn in ``[0.9, 1.75]`` (the arms overlap a lot;
  about 40 % of the problems have no plan);
- buffers (one number, or one per positioner), and collision-free start and target
  configurations drawn positioner by positioner, uniformly among the positions
  compatible with those already placed (the oracle's own static tables).

A seed ending in 7 (one in ten) uses *round* numbers instead (arm 15, bases 19 apart,
buffers 2: arms that touch at exactly the buffer sum), the ties of the collision rule.
Nothing here imports the project's geometry.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .model import Arm, OracleInputError, hex_bases
from .sweep import TIE
from .tables import PairTables

__all__ = ["KINDS", "MAX_PRODUCT", "tight_problem"]

#: the largest number of configurations of a drawn problem
MAX_PRODUCT = 1_000_000
KINDS = ("rotary", "alpha-beta")
#: neighbour distance / reach, drawn uniformly in these ranges
TIGHT = {"rotary": (0.45, 1.2), "alpha-beta": (0.45, 1.0)}
_AB_SHAPES = [(a, b) for a in (4, 5, 6, 8, 10, 12) for b in (2, 3, 4, 5, 7)]


def _kinematics(rng: np.random.Generator, kind: str, n: int, round_numbers: bool, product: int) -> dict:
    cap = int(product ** (1.0 / n) + 1e-9)
    if kind == "rotary":
        steps = int(rng.integers(min(6, cap), min(24, cap) + 1))
        arm = 15.0 if round_numbers else round(float(rng.uniform(8.0, 16.0)), 3)
        return {"kind": "rotary", "arm": arm, "steps": steps}
    shapes = [s for s in _AB_SHAPES if s[0] * s[1] <= cap] or [s for s in ((3, 2),) if s[0] * s[1] <= cap]
    if not shapes:
        raise OracleInputError(f"no alpha-beta discretisation of {n} positioners within {product} configurations",
                               value=product)
    a_steps, b_steps = shapes[int(rng.integers(len(shapes)))]
    ranges = [[0.0, 180.0], [-30.0, 190.0], [150.0, 180.0], [120.0, 180.0], [140.0, 200.0]]
    alpha, beta = (7.5, 15.0) if round_numbers else (round(float(rng.uniform(5.0, 9.0)), 3),
                                                     round(float(rng.uniform(9.0, 16.0)), 3))
    return {"kind": "alpha-beta", "alpha": alpha, "beta": beta, "alpha_steps": a_steps, "beta_steps": b_steps,
            "beta_range": ranges[int(rng.integers(len(ranges)))]}


def _layout(rng: np.random.Generator, n: int, reach: float, round_numbers: bool,
            tight: tuple[float, float]) -> tuple[str, list[list[float]]]:
    shape = ["line", "hex", "cluster"][int(rng.integers(3))]
    spacing = 19.0 if round_numbers else float(rng.uniform(*tight)) * reach
    if shape == "line":
        pts = [complex(k * spacing, 0.0) for k in range(n)]
    elif shape == "hex":
        pts = list(hex_bases(2, spacing)[:n])
    else:
        pts = [0j]
        while len(pts) < n:
            anchor = pts[int(rng.integers(len(pts)))]
            cand = anchor + spacing * complex(math.cos(a := float(rng.uniform(0, 2 * math.pi))), math.sin(a))
            if all(abs(cand - p) >= 0.8 * spacing for p in pts):
                pts.append(cand)
    return shape, [[round(p.real, 6), round(p.imag, 6)] for p in pts]


def _configuration(rng: np.random.Generator, arm: Arm, bases: np.ndarray, buffers: np.ndarray,
                   cache: dict) -> list[int] | None:
    n, npos = len(bases), arm.n_positions
    conf: list[int] = []
    for p in range(n):
        free = np.ones(npos, dtype=bool)
        for q in range(p):
            key = (p, q)
            if key not in cache:
                cache[key] = PairTables(arm, complex(bases[q] - bases[p]), float(buffers[p] + buffers[q]))
            t = cache[key]
            if not t.far:  # clear of every neighbour placed, by more than a tie
                free &= t.static_gap()[:, conf[q]] >= t.need + TIE
        choices = np.nonzero(free)[0]
        if not len(choices):
            return None
        conf.append(int(rng.choice(choices)))
    return conf


def tight_problem(seed: int, kind: str | None = None, n: int | None = None,
                  max_product: int = MAX_PRODUCT) -> dict[str, Any]:
    """A random tight problem (module docstring) as PROBLEM.json; ``kind``/``n`` override the
    draw, ``max_product`` lowers the bound on the number of configurations."""
    rng = np.random.default_rng(seed)
    round_numbers = seed % 10 == 7
    kind = kind or KINDS[int(rng.integers(2))]
    n = int(n or rng.integers(2, 7))
    kin = _kinematics(rng, kind, n, round_numbers, max_product)
    arm = Arm.from_json(kin)
    for _ in range(50):
        shape, xy = _layout(rng, n, arm.reach, round_numbers, TIGHT[kind])
        if round_numbers:
            buffer: Any = 2.0
        elif rng.random() < 0.5:
            buffer = round(float(rng.uniform(0.5, 2.5)), 3)
        else:
            buffer = [round(float(v), 3) for v in rng.uniform(0.5, 2.5, n)]
        bases = np.array([complex(x, y) for x, y in xy])
        buffers = np.broadcast_to(np.asarray(buffer, dtype=float), (n,))
        cache: dict = {}
        start = _configuration(rng, arm, bases, buffers, cache)
        target = _configuration(rng, arm, bases, buffers, cache)
        if start is None or target is None:
            continue
        rows = arm.positions().tolist()
        ends = [[rows[i][0] if kind == "rotary" else rows[i] for i in conf] for conf in (start, target)]
        return {"layout": {"kind": "points", "xy": xy}, "kinematics": kin, "collision": {"buffer": buffer},
                "start": ends[0], "target": ends[1],
                "name": f"tight {kind} {n} {shape}", "seed": int(seed)}
    raise OracleInputError(f"seed {seed}: no collision-free configuration in 50 layouts", value=seed)
