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

``tight_angle_problem(seed, n)`` draws problems of the extensions for real instruments:
alpha-beta robots (2–5; ``alpha_steps`` 4–8, ``beta_steps`` 3–5) whose starts and targets
are exact joint angles (``alpha_beta_deg``; sometimes one side as indices, sometimes as
fibre positions ``xy_mm`` with a handedness), so every robot gets its own lattice; the
alpha joint wraps or has hard stops (``alpha_range``, often ``[0, 360]``); sometimes a
``collision.margin``.  Starts and targets are drawn robot by robot, uniformly over the
joint ranges (or among the uniform positions), clear of the robots already placed by
10⁻⁶ mm more than the rule needs (the oracle's own segment distance).
Nothing here imports the project's geometry.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .angles import uniform_deg
from .distance import segment_gap
from .oracle_model import Arm, OracleInputError, OracleProblem, hex_bases
from .certified_sweep import TIE
from .tables import PairTables

__all__ = ["ANGLE_MAX_PRODUCT", "KINDS", "MAX_PRODUCT", "tight_angle_problem", "tight_problem"]

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


#: the largest number of configurations of a drawn angle problem
ANGLE_MAX_PRODUCT = 250_000
#: the alpha joint: wrapping (None) or hard stops; beta ranges
_ALPHA_RANGES = [None, None, None, [0.0, 360.0], [0.0, 360.0], [-180.0, 180.0], [-30.0, 300.0]]
_BETA_RANGES = [[0.0, 180.0], [0.0, 180.0], [-30.0, 190.0], [120.0, 180.0], [-10.0, 200.0]]
#: clearance over the rule's need of every drawn start and target (mm): no ties
_CLEAR = 1e-6


def _pose(a: float, b: float, alpha_deg: float, beta_deg: float) -> tuple[complex, complex]:
    al, be = math.radians(alpha_deg), math.radians(beta_deg)
    elbow = a * complex(math.cos(al), math.sin(al))
    return elbow, elbow + b * complex(math.cos(al + be), math.sin(al + be))


def _angle_conf(rng: np.random.Generator, kin: dict, bases: list[complex], need: np.ndarray, grid: bool,
                avoid: dict | None = None) -> list[tuple[float, float]] | None:
    """Collision-free exact angles, robot by robot; ``grid``: uniform positions only."""
    a, b = kin["alpha"], kin["beta"]
    arange = kin.get("alpha_range")
    alo, ahi = (0.0, 360.0) if arange is None else arange
    blo, bhi = kin["beta_range"]
    ga = uniform_deg(kin["alpha_steps"], arange is None, alo, ahi)
    gb = uniform_deg(kin["beta_steps"], False, blo, bhi)
    conf: list[tuple[float, float]] = []
    segs: list[tuple[complex, complex]] = []
    for p in range(len(bases)):
        for _ in range(300):
            if grid or rng.random() < 0.15:
                al, be = float(ga[rng.integers(len(ga))]), float(gb[rng.integers(len(gb))])
            else:
                al, be = float(rng.uniform(alo, ahi)), float(rng.uniform(blo, bhi))
                if arange is None:
                    al %= 360.0
            e, f = _pose(a, b, al, be)
            e, f = e + bases[p], f + bases[p]
            if all(float(segment_gap(e, f, s0, s1)) >= need[p, q] + _CLEAR for q, (s0, s1) in enumerate(segs)):
                break
        else:
            return None
        conf.append((al, be))
        segs.append((e, f))
    return conf


def _fibre_ok(kin: dict, conf: list[tuple[float, float]]) -> bool:
    """Every pose well away from a folded or straight beta arm and the joint ends (inverse
    kinematics are ill-conditioned there, and rounding could leave a range)."""
    blo, bhi = kin["beta_range"]
    arange = kin.get("alpha_range")
    for al, be in conf:
        if abs(math.sin(math.radians(be))) < 0.05 or not blo + 0.01 < be < bhi - 0.01:
            return False
        if arange is not None and not arange[0] + 0.01 < al < arange[1] - 0.01:
            return False
    return True


def _angle_kinematics(rng: np.random.Generator, n: int | None, max_product: int) -> tuple[int, dict[str, Any]]:
    """The number of robots and their alpha-beta kinematics, with at most ``max_product``
    configurations in all."""
    sizes = [k for k in (2, 2, 3, 3, 3, 4, 4, 5) if 12**k <= max_product] or [2]
    n = int(n or rng.choice(sizes))
    cap = int(max_product ** (1.0 / n) + 1e-9)
    shapes = [(x, y) for x in range(4, 9) for y in range(3, 6) if x * y <= cap]
    if not shapes:
        raise OracleInputError(f"no discretisation of {n} robots within {max_product} configurations",
                               value=max_product)
    a_steps, b_steps = shapes[int(rng.integers(len(shapes)))]
    kin: dict[str, Any] = {"kind": "alpha-beta", "alpha": round(float(rng.uniform(5.0, 9.0)), 3),
                           "beta": round(float(rng.uniform(9.0, 16.0)), 3), "alpha_steps": int(a_steps),
                           "beta_steps": int(b_steps),
                           "beta_range": _BETA_RANGES[int(rng.integers(len(_BETA_RANGES)))]}
    arange = _ALPHA_RANGES[int(rng.integers(len(_ALPHA_RANGES)))]
    if arange is not None:
        kin["alpha_range"] = list(arange)
    elif a_steps < 4:
        kin["alpha_steps"] = 4
    return n, kin


def _end_forms(rng: np.random.Generator) -> list[str]:
    """How the start and the target are written: ``deg`` (angles), ``index`` or ``xy``."""
    forms = ["deg", "deg"]
    r = rng.random()
    if r < 0.25:
        forms[int(rng.integers(2))] = "index"
    elif r < 0.5:
        forms[int(rng.integers(2))] = "xy"
    elif r < 0.6:
        forms = ["xy", "xy"]
    return forms


def _xy_side(rng: np.random.Generator, kin: dict, bases: list[complex],
             conf: list[tuple[float, float]]) -> dict[str, Any] | None:
    """``conf`` as fibre positions with a handedness, or None where the robots' hands differ."""
    pts, hands = [], []
    for p, (al, be) in enumerate(conf):
        _, f = _pose(kin["alpha"], kin["beta"], al, be)
        f += bases[p]
        pts.append([float(f.real), float(f.imag)])
        hands.append("right" if math.sin(math.radians(be)) > 0 else "left")
    if len(set(hands)) == 1 and hands[0] == "right":
        hand = "right" if rng.random() < 0.5 else "any"
    elif len(set(hands)) == 1:
        hand = "left"
    else:
        return None
    return {"xy_mm": pts, "handedness": hand}


def _side(rng: np.random.Generator, form: str, kin: dict, bases: list[complex],
          conf: list[tuple[float, float]]) -> Any:
    """The start or target ``conf`` (exact angles) written in ``form`` (``xy`` falls back to
    angles where inverse kinematics would be ill-conditioned or the hands differ)."""
    arange = kin.get("alpha_range")
    if form == "xy" and not _fibre_ok(kin, conf):
        form = "deg"
    if form == "index":
        ga = uniform_deg(kin["alpha_steps"], arange is None, *(arange or (0.0, 360.0)))
        gb = uniform_deg(kin["beta_steps"], False, *kin["beta_range"])
        return [[int(np.argmin(np.abs(ga - al))), int(np.argmin(np.abs(gb - be)))] for al, be in conf]
    if form == "xy":
        side = _xy_side(rng, kin, bases, conf)
        return side if side is not None else {"alpha_beta_deg": [[al, be] for al, be in conf]}
    rows = []
    for al, be in conf:  # a wrapping alpha may come as any turn
        if arange is None and rng.random() < 0.2:
            al = al + 360.0 * float(rng.choice([-1, 1]))
        rows.append([al, be])
    return {"alpha_beta_deg": rows}


def _angle_problem_on_a_layout(rng: np.random.Generator, seed: int, n: int, kin: dict, arm: Arm, margin: float,
                               tight: tuple[float, float]) -> dict[str, Any] | None:
    """One draw of a layout, buffers, start and target for ``tight_angle_problem``, or None
    where no collision-free ends were found or the oracle refuses the problem."""
    shape, xy = _layout(rng, n, arm.reach, False, tight)
    buffer: Any = (round(float(rng.uniform(0.8, 3.0)), 3) if rng.random() < 0.6
                   else [round(float(v), 3) for v in rng.uniform(0.8, 3.0, n)])
    bases = [complex(x, y) for x, y in xy]
    buf = np.broadcast_to(np.asarray(buffer, dtype=float), (n,))
    need = buf[:, None] + buf[None, :] + margin
    forms = _end_forms(rng)
    ends = [_angle_conf(rng, kin, bases, need, grid=form == "index") for form in forms]
    if any(e is None for e in ends):
        return None
    sides = [_side(rng, form, kin, bases, conf) for form, conf in zip(forms, ends)]
    collision: dict[str, Any] = {"buffer": buffer}
    if margin:
        collision["margin"] = margin
    data = {"layout": {"kind": "points", "xy": xy}, "kinematics": kin, "collision": collision,
            "start": sides[0], "target": sides[1],
            "name": f"tight angles {n} {shape} {'/'.join(forms)}", "seed": int(seed)}
    try:
        OracleProblem.from_json(data)
    except OracleInputError:
        return None
    return data


def tight_angle_problem(seed: int, n: int | None = None, max_product: int = ANGLE_MAX_PRODUCT,
                        tight: tuple[float, float] = (0.25, 0.6)) -> dict[str, Any]:
    """A random tight problem with exact start and target angles (module docstring) as
    PROBLEM.json; ``n`` overrides the number of robots (2–5), ``max_product`` bounds the
    number of configurations, ``tight`` the range of neighbour distance / reach."""
    rng = np.random.default_rng(seed)
    n, kin = _angle_kinematics(rng, n, max_product)
    arm = Arm.from_json(kin)
    margin = round(float(rng.uniform(0.2, 1.5)), 3) if rng.random() < 0.35 else 0.0
    for _ in range(50):
        data = _angle_problem_on_a_layout(rng, seed, n, kin, arm, margin, tight)
        if data is not None:
            return data
    raise OracleInputError(f"seed {seed}: no collision-free angles in 50 layouts", value=seed)
