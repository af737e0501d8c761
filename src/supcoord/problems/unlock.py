"""Robot lattices that do not lock a robot in among its obstacles.

Each robot's own lattice holds its exact start and target angles
(:func:`.targets.robot_lattices`).  Beside a fixed obstacle (a fiducial, a guide camera)
or under a joint rule, a coarse lattice can leave a robot **no path even alone** where its
real joint space has one: on SDSS-V's APO wok (kaiju's instance seed 1, fold, 13 × 7),
robot 386 starts at (8.1°, 31.3°); at β = 60° a fiducial is within 5 mm for α ∈ {8.1°, 10°},
and at α = 60° for β ≤ 31.3°, so on its lattice it is boxed in, while it can swing α down
to 3° and fold there.  No plan on that lattice exists, and the planner would answer
"infeasible" about the lattice, not about the instrument.

:func:`unlock_lattices` checks every robot with constraints of its own (:meth:`Problem.unary`:
obstacles, joint rules; held robots never move) alone on its lattice (breadth-first over
its positions, the other robots removed).  Where the target is out of reach, it searches a
fine lattice of the same joints (about :data:`FINE_POSITIONS` positions) for a path of
single-joint moves with the fewest turns (:func:`scipy.sparse.csgraph.dijkstra` over
``(position, joint)`` nodes: a turn costs 1, a step :data:`STEP_COST`), and rebuilds the
robot's lattice so that it also holds the angles of the path's corners
(:func:`lattice_holding`).  A path of single-joint moves between corners is then a path of
the new lattice, with the same motion; the new lattice is checked alone again and kept
only if the target is reachable on it.  The problem's warnings say which robots changed.

Starts and targets keep their exact angles; the lattice stays a function of the problem
file, so ``supcoord check`` reads plans on the same lattices as ``supcoord solve``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, dijkstra

from ..geometry.alpha_beta import AlphaBeta
from ..geometry.joint_space import MAX_POSITIONS

__all__ = ["unlock_lattices", "with_lattices", "LatticeChange", "lattice_holding", "alone_reachable", "corner_angles", "FINE_POSITIONS"]

#: positions of the fine lattice a locked-in robot's path is searched on (one robot's
#: obstacle tables only: a few milliseconds)
FINE_POSITIONS = 6000
#: cost of one step against a turn's 1: among the paths with fewest turns, a shortest
STEP_COST = 1e-3


def _move_graph(kin: AlphaBeta, U: np.ndarray, V: np.ndarray) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Per move ``m``: the flat positions it may start from and the positions it reaches
    (neither end refused by ``U``, the move not by ``V``)."""
    pos = kin.all_positions()
    srcs, dsts = [], []
    for m, (joint, d) in enumerate(kin.moves()):
        nxt, ok = kin.step_array(pos, joint, d)
        ok &= ~V[m] & ~U
        src = np.flatnonzero(ok)
        dst = kin.flat_index(nxt[ok])
        keep = ~U[dst]
        srcs.append(src[keep])
        dsts.append(np.asarray(dst)[keep])
    return srcs, dsts


def alone_reachable(kin: AlphaBeta, tables: tuple[np.ndarray, np.ndarray], start: np.ndarray,
                    target: np.ndarray) -> bool:
    """Can a robot with kinematics ``kin`` and own tables ``(U, V)`` go from ``start`` to
    ``target`` (indices) by single moves, no other robot present?"""
    U, V = tables
    srcs, dsts = _move_graph(kin, U, V)
    n = kin.n_positions
    graph = coo_matrix((np.ones(sum(len(s) for s in srcs)), (np.concatenate(srcs), np.concatenate(dsts))),
                       shape=(n, n)).tocsr()
    seen = breadth_first_order(graph, int(kin.flat_index(start)), directed=True, return_predecessors=False)
    return int(kin.flat_index(target)) in set(seen.tolist())


def _fine_kinematics(kin: AlphaBeta, exact: list[tuple[float, float]]) -> AlphaBeta:
    """``kin`` on a uniform lattice of about :data:`FINE_POSITIONS` positions that also holds
    the angles ``exact``."""
    a_lo, a_hi = kin.alpha_range if kin.alpha_range is not None else (0.0, 360.0)
    b_lo, b_hi = kin.beta_range
    spans = (a_lo, a_hi), (b_lo, b_hi)
    h = math.sqrt((a_hi - a_lo) * (b_hi - b_lo) / FINE_POSITIONS)
    counts = [max(2, int(round((hi - lo) / h)) + 1) for lo, hi in spans]
    extra = len(exact)  # the exact angles may each add a position per joint
    while (counts[0] + extra) * (counts[1] + extra) > MAX_POSITIONS:  # a very uneven pair of ranges
        big = int(counts[1] > counts[0])
        counts[big] = max(2, counts[big] * 9 // 10)
    tables = []
    for j, ((lo, hi), n) in enumerate(zip(spans, counts)):
        top = hi if j == 1 or kin.alpha_range is not None else hi - (hi - lo) / n  # a wrapping α: one turn
        grid = np.linspace(lo, top, n)
        tables.append(np.unique(np.concatenate([grid, [e[j] for e in exact]])))
    return AlphaBeta(kin.alpha, kin.beta, len(tables[0]), len(tables[1]), kin.beta_range,
                     alpha_range=kin.alpha_range, alpha_deg=tables[0], beta_deg=tables[1], segment=kin.segment,
                     fibre_point=kin.fibre_point, offsets=kin.offsets)


def _fewest_turns(kin: AlphaBeta, tables: tuple[np.ndarray, np.ndarray], start: int,
                  target: int) -> list[tuple[float, float]] | None:
    """The corners (angles) of a single-move path ``start → target`` (flat indices) with the
    fewest turns, or None if there is none."""
    U, V = tables
    n = kin.n_positions
    srcs, dsts = _move_graph(kin, U, V)
    joints = [joint for joint, _ in kin.moves()]
    rows = [s * 2 + j for s, j in zip(srcs, joints)] + [np.arange(n) * 2, np.arange(n) * 2 + 1]
    cols = [d * 2 + j for d, j in zip(dsts, joints)] + [np.arange(n) * 2 + 1, np.arange(n) * 2]
    cost = [np.full(len(s), STEP_COST) for s in srcs] + [np.ones(n), np.ones(n)]
    graph = coo_matrix((np.concatenate(cost), (np.concatenate(rows), np.concatenate(cols))),
                       shape=(2 * n, 2 * n)).tocsr()
    dist, pred, _ = dijkstra(graph, indices=[2 * start, 2 * start + 1], return_predecessors=True, min_only=True)
    end = min((2 * target, 2 * target + 1), key=lambda x: dist[x])
    if not np.isfinite(dist[end]):
        return None
    nodes = [end]
    while nodes[-1] not in (2 * start, 2 * start + 1):
        nodes.append(int(pred[nodes[-1]]))
    positions = [x // 2 for x in reversed(nodes)]
    angles = kin.joint_angles_deg(kin.all_positions()[positions])
    corners = [tuple(float(v) for v in angles[0])]
    for i in range(1, len(positions) - 1):
        if positions[i] == positions[i - 1] or positions[i] == positions[i + 1]:  # a turn happens here
            corners.append(tuple(float(v) for v in angles[i]))
    corners.append(tuple(float(v) for v in angles[-1]))
    return [c for i, c in enumerate(corners) if i == 0 or c != corners[i - 1]]


def corner_angles(corners: list[tuple[float, float]]) -> list[list[float]]:
    """``[α values, β values]`` a lattice must hold for the single-joint path through
    ``corners`` to be one of its paths: the α at which β moves and the β at which α moves."""
    need: list[list[float]] = [[], []]
    for a, b in zip(corners, corners[1:]):
        moving = 0 if a[0] != b[0] else 1
        need[1 - moving].append(a[1 - moving])
    return need


def _slots(kin: AlphaBeta, angles: tuple[float, float]) -> np.ndarray:
    """The position of ``kin``'s lattice at exactly ``angles``."""
    return np.array([int(np.flatnonzero(kin.lattice_deg(j) == angles[j])[0]) for j in (0, 1)])


def lattice_holding(table: np.ndarray, needed: list[float], keep: list[float], wraps: bool) -> np.ndarray | None:
    """A strictly increasing lattice of ``len(table)`` angles holding ``needed`` and ``keep``
    (values of ``table`` to keep: the exact start and target), the other values of
    ``table`` dropped where they sit closest to a neighbour (the gap they leave is the
    smallest), the ends of a joint with hard stops kept; None if the values do not fit."""
    n = len(table)
    fixed = set(float(v) for v in needed) | set(float(v) for v in keep)
    values = sorted(set(float(v) for v in table) | fixed)
    if len(fixed) > n:
        return None
    while len(values) > n:
        best, drop = math.inf, None
        for i, v in enumerate(values):
            if v in fixed or (not wraps and i in (0, len(values) - 1)):
                continue
            lo = values[i - 1] if i > 0 else values[-1] - 360.0
            hi = values[i + 1] if i + 1 < len(values) else values[0] + 360.0
            if hi - lo < best:
                best, drop = hi - lo, i
        if drop is None:
            return None
        values.pop(drop)
    return np.array(values)


def _with_row(rows: np.ndarray, p: int, value: Any) -> np.ndarray:
    """A read-only copy of ``rows`` with row ``p`` set to ``value`` (a problem's arrays are
    read-only: nothing changes them behind its caches)."""
    out = rows.copy()
    out[p] = value
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class LatticeChange:
    """One robot's rebuilt lattice (:func:`unlock_lattices`): its kinematics, its start and
    target positions on it, and the warning that tells the user."""

    robot: int
    kinematics: AlphaBeta
    start: np.ndarray
    target: np.ndarray
    warning: str


def unlock_lattices(problem: Any) -> list[LatticeChange]:
    """The rebuilt lattice of every robot that cannot reach its target alone on its own
    lattice but can on a fine one (module docstring); ``problem`` is left as it is
    (:func:`with_lattices` makes the problem with the changes)."""
    kins = problem.robot_kinematics
    if kins is None or not (len(problem.obstacles) or problem.joint_rules):
        return []
    changed: list[LatticeChange] = []
    for p, tables in sorted(problem.unary().items()):
        kin = kins[p]
        if p in problem.held or not isinstance(kin, AlphaBeta):
            continue
        if alone_reachable(kin, tables, problem.start[p], problem.target[p]):
            continue
        start, target = (tuple(float(v) for v in kin.joint_angles_deg(c[p])) for c in (problem.start, problem.target))
        fine = _fine_kinematics(kin, [start, target])
        fine_tables = problem.own_tables(p, fine)
        s_fine, t_fine = (int(fine.flat_index(_slots(fine, a))) for a in (start, target))
        corners = _fewest_turns(fine, fine_tables, s_fine, t_fine)
        if corners is None:
            continue  # locked in for real (at the fine lattice too): the planner's certificate says so
        need = corner_angles(corners)
        wraps = kin.alpha_range is None
        tabs = [lattice_holding(kin.lattice_deg(j), need[j], [start[j], target[j]], wraps and j == 0) for j in (0, 1)]
        if tabs[0] is None or tabs[1] is None:
            continue
        new = AlphaBeta(kin.alpha, kin.beta, kin.alpha_steps, kin.beta_steps, kin.beta_range,
                        alpha_range=kin.alpha_range, alpha_deg=tabs[0], beta_deg=tabs[1], segment=kin.segment,
                        fibre_point=kin.fibre_point, offsets=kin.offsets)
        s_new, t_new = (_slots(new, a) for a in (start, target))
        new_tables = problem.own_tables(p, new)
        if new_tables is None or not alone_reachable(new, new_tables, s_new, t_new):
            continue
        added = ", ".join(f"{name} {v:g}" for name, vals in zip(("alpha", "beta"), need) for v in sorted(set(vals))
                          if v not in kin.lattice_deg(0 if name == "alpha" else 1))
        changed.append(LatticeChange(p, new, s_new, t_new, f"robot {p}: its obstacles leave it no path on its lattice; "
                                     f"the lattice now also holds {added} deg (a path around them)"))
    return changed


def with_lattices(problem: Any, changes: list[LatticeChange]) -> Any:
    """``problem`` with the rebuilt lattices ``changes`` (:func:`unlock_lattices`): a new
    :class:`~supcoord.problems.problem.Problem` (robots' kinematics, start and target
    indices, warnings; its caches computed afresh), or ``problem`` itself when there are none."""
    if not changes:
        return problem
    kins, start, target = list(problem.robot_kinematics), problem.start, problem.target
    for change in changes:
        kins[change.robot] = change.kinematics
        start, target = _with_row(start, change.robot, change.start), _with_row(target, change.robot, change.target)
    return replace(problem, robot_kinematics=kins, start=start, target=target,
                   warnings=list(problem.warnings) + [c.warning for c in changes], _tables=None, _pairs=None,
                   _unary=None)
