"""Breadth-first search over joint configurations, on the oracle's own tables.

The **single-move semantics** of ``docs/formats.md`` over the members ``P`` (everyone,
or a sub-problem with every other positioner *removed*): a configuration ``c`` gives
each member a position id; a move turns one joint of one member by ``±1`` (wrapping
joints wrap, the others stop at their ends)::

    c → c[p ↦ step(c_p, k, ±1)]   allowed iff  ∀ q ∈ P∖{p}: the swept motion of p is free
                                                of q standing at c_q   (.tables edges)

(the swept motion includes both ends, so every configuration reached from the
collision-free start is collision-free).  The **simultaneous semantics**: in one step
every joint of every member moves by −1, 0 or +1 at once, allowed iff every pair's
simultaneous motion is free (``.tables`` ``simultaneous``) — the optimal makespan.

Configurations are mixed-radix integers ``Σ_p c_p·n^{k−1−p}`` (``n`` positions per
member, ``k`` members); the search is level by level over numpy frontiers (Moore's BFS),
refusing more than :data:`MAX_CONFIGURATIONS` configurations.

**Undecided entries** (:data:`.certified_sweep.UNDECIDED`) are never given a side.  The search runs
with them blocked; if it read one, it runs again with them free.  Distances only shrink
and reachable sets only grow as edges are added, so the true graph lies between the two:
equal answers are the exact answer (and a path of the first run uses decided edges
only); different answers raise :class:`OracleUndecided`.

References
----------
- E. F. Moore, The shortest path through a maze, Proc. Int. Symp. Theory of Switching, 1959.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from .oracle_model import OracleInputError, OracleProblem
from .certified_sweep import FREE, TIE, UNDECIDED
from .tables import PairTables, joint_options

__all__ = ["MAX_CONFIGURATIONS", "MAX_STEP_KINDS", "OracleUndecided", "Outcome", "Space"]

#: refuse searches over more configurations than this
MAX_CONFIGURATIONS = 4_000_000
#: refuse simultaneous searches with more kinds of steps per configuration than this
MAX_STEP_KINDS = 20_000


class OracleUndecided(RuntimeError):
    """The answer depends on swept entries the oracle could not decide to 10⁻⁹ mm."""


@dataclass
class Outcome:
    """One search: ``distance`` (None: unreachable), ``reachable`` (configurations seen,
    exact only for a search to exhaustion), ``moves`` (a shortest path) and
    ``undecided`` (undecided table entries the search read)."""

    distance: int | None
    reachable: int
    moves: list[tuple[int, int, int]] | None
    undecided: int
    #: the configurations seen (codes, :meth:`Space.encode`), for a search to exhaustion
    seen: np.ndarray | None = None


class Space:
    """The configurations of ``members`` of a problem and their tables (module docstring)."""

    def __init__(self, prob: OracleProblem, members: list[int] | None = None,
                 cache: dict | None = None, replay_only: bool = False):
        self.prob = prob
        self.members = list(range(prob.n)) if members is None else sorted({int(p) for p in members})
        if not self.members or not all(0 <= p < prob.n for p in self.members):
            raise OracleInputError(f"members must be positioners of the problem, got {members}", value=members)
        arm = prob.arm
        self.n, self.k = arm.n_positions, len(self.members)
        self.total = self.n ** self.k
        if self.total > MAX_CONFIGURATIONS and not replay_only:  # replaying a plan needs only the pair tables
            raise OracleInputError(f"explicit search over {self.total} configurations exceeds {MAX_CONFIGURATIONS}",
                                   value=self.total)
        self.weight = np.array([self.n ** (self.k - 1 - a) for a in range(self.k)], dtype=np.int64)
        self.cache = {} if cache is None else cache
        #: (a, b, tables): member indices a < b that can collide, tables in a's frame
        self.pairs: list[tuple[int, int, PairTables]] = []
        for a, b in itertools.combinations(range(self.k), 2):
            pa, pb = self.members[a], self.members[b]
            t = self._tables(prob.bases[pb] - prob.bases[pa], prob.need(pa, pb), prob.arm_of(pa), prob.arm_of(pb))
            if not t.far:
                self.pairs.append((a, b, t))
        for name, conf in (("start", prob.start), ("target", prob.target)):
            for a, b, t in self.pairs:
                d = t.static_gap()[conf[self.members[a]], conf[self.members[b]]]
                if d < t.need - TIE:  # a tie is the problem's own business: its moves will tell
                    raise OracleInputError(f"{name} configuration collides: positioners {self.members[a]} and "
                                           f"{self.members[b]} are {d:.6f} mm apart, less than {t.need}",
                                           value=[self.members[a], self.members[b]])

    def _tables(self, offset: complex, need: float, arm_a=None, arm_b=None) -> PairTables:
        """The tables of a pair, shared by (offset, need) between pairs of identical robots and
        by (offset, need, a's arm, b's arm) where robots have their own lattices."""
        arm_a = self.prob.arm if arm_a is None else arm_a
        arm_b = self.prob.arm if arm_b is None else arm_b
        key = (offset.real, offset.imag, float(need))
        if arm_a is not self.prob.arm or arm_b is not self.prob.arm:
            key += (arm_a, arm_b)
        if key not in self.cache:
            self.cache[key] = PairTables(arm_a, offset, need, arm_b)
        return self.cache[key]

    def encode(self, ids: list[int]) -> int:
        return int(sum(ids[p] * w for p, w in zip(self.members, self.weight.tolist())))

    def digits(self, conf: np.ndarray) -> np.ndarray:
        return (conf[:, None] // self.weight[None, :]) % self.n

    # -- the single-move semantics -------------------------------------------------------
    def moves(self) -> list[tuple[int, int]]:
        return [(j, d) for j in range(self.prob.arm.n_joints) for d in (1, -1)]

    def _blocked(self) -> tuple[np.ndarray, dict[tuple[int, int], np.ndarray]]:
        """``nxt[m, i]`` and ``blk[(a, b)][m, i, j]``: member ``a`` moving ``m`` from ``i``
        past member ``b`` at ``j`` (uint8, three-valued)."""
        arm = self.prob.arm
        moves = self.moves()
        deltas = np.zeros((len(moves), arm.n_joints), dtype=np.int64)
        for m, (j, d) in enumerate(moves):
            deltas[m, j] = d
        nxt = arm.successors(deltas)
        blk: dict[tuple[int, int], np.ndarray] = {}
        for a, b, t in self.pairs:
            for mover, other, side in ((a, b, 0), (b, a, 1)):
                out = np.empty((len(moves), self.n, self.n), dtype=np.uint8)
                for m, (j, d) in enumerate(moves):
                    e = t.edge(side, j)
                    e = e if side == 0 else e.T  # [mover position, other position]
                    if d == 1:
                        out[m] = e
                    else:  # −1 from i is the edge +1 from step(i, −1), read backwards
                        prev = nxt[m]
                        out[m] = np.where((prev >= 0)[:, None], e[np.maximum(prev, 0)], 1)
                blk[(mover, other)] = out
        return nxt, blk

    def single(self, goal: bool = True, path: bool = False, bounds: bool = False):
        """Shortest single-move distance start → target (``goal``) or the whole reachable set."""
        nxt, blk = self._blocked()
        steps = [(a, m) for a in range(self.k) for m in range(len(self.moves()))]

        def succ(frontier: np.ndarray, lenient: bool) -> tuple[list, int]:
            dig = self.digits(frontier)
            out, undecided = [], 0
            for code, (a, m) in enumerate(steps):
                new = nxt[m][dig[:, a]]
                ok = new >= 0
                for (mover, other), table in blk.items():
                    if mover == a:
                        entry = table[m][dig[:, a], dig[:, other]]
                        und = ok & (entry == UNDECIDED)
                        undecided += int(und.sum())
                        ok &= (entry == FREE) | (und if lenient else False)
                nbr = frontier[ok] + (new[ok] - dig[ok, a]) * self.weight[a]
                out.append((nbr, frontier[ok], code))
            return out, undecided

        return self._two_sided(succ, goal, path, lambda code: (self.members[steps[code][0]],)
                               + self.moves()[steps[code][1]], bounds)

    # -- the simultaneous semantics ------------------------------------------------------
    def simultaneous(self) -> Outcome:
        """Fewest simultaneous steps start → target (module docstring)."""
        opts = joint_options(self.prob.arm)
        kinds = len(opts) ** self.k - 1
        if kinds > MAX_STEP_KINDS:
            raise OracleInputError(f"{kinds} simultaneous steps per configuration exceed {MAX_STEP_KINDS}",
                                   value=kinds)
        nxt = self.prob.arm.successors(opts)
        combos = [c for c in itertools.product(range(len(opts)), repeat=self.k) if any(c)]
        tables = [(a, b, t.simultaneous()) for a, b, t in self.pairs]

        def succ(frontier: np.ndarray, lenient: bool) -> tuple[list, int]:
            dig = self.digits(frontier)
            out, undecided = [], 0
            for code, combo in enumerate(combos):
                new = np.stack([nxt[u][dig[:, a]] for a, u in enumerate(combo)], axis=1)
                ok = np.all(new >= 0, axis=1)
                for a, b, sim in tables:
                    if combo[a] == 0 and combo[b] == 0:
                        continue  # neither moves: the current configuration is free
                    entry = sim[combo[a], combo[b]][dig[:, a], dig[:, b]]
                    und = ok & (entry == UNDECIDED)
                    undecided += int(und.sum())
                    ok &= (entry == FREE) | (und if lenient else False)
                nbr = (new[ok] * self.weight[None, :]).sum(axis=1)
                out.append((nbr, frontier[ok], code))
            return out, undecided

        return self._two_sided(succ, True, False, lambda code: combos[code])

    # -- checking a given plan -----------------------------------------------------------
    def check_moves(self, moves: list[tuple[int, int, int]]) -> int | None:
        """Replay single moves ``(positioner, joint, ±1)`` of members from the start: the
        index of the first one past a hard stop or not certified free (``HIT`` or
        ``UNDECIDED``), ``len(moves)`` if they end elsewhere than the target, else ``None``."""
        nxt, blk = self._blocked()
        kinds = self.moves()
        where = {p: a for a, p in enumerate(self.members)}
        conf = [self.prob.start[p] for p in self.members]
        for k, (p, j, d) in enumerate(moves):
            if int(p) not in where or (int(j), int(d)) not in kinds:
                return k
            a, m = where[int(p)], kinds.index((int(j), int(d)))
            new = int(nxt[m][conf[a]])
            if new < 0:
                return k
            for (mover, other), table in blk.items():
                if mover == a and table[m][conf[a], conf[other]] != FREE:
                    return k
            conf[a] = new
        return None if conf == [self.prob.target[p] for p in self.members] else len(moves)

    def check_steps(self, configurations: list) -> int | None:
        """Check a schedule of configurations (``(N, J)`` joint indices, every robot) under
        the simultaneous semantics: the index of the first step whose joints move by more
        than one position or whose motion is not certified free for some pair (``k`` for the
        step ``k → k + 1``), ``len(configurations)`` if it does not run from the start to the
        target, else ``None``."""
        arm = self.prob.arm
        steps = np.array(arm.steps)
        confs = [np.asarray(c, dtype=np.int64).reshape(self.prob.n, arm.n_joints)[self.members]
                 for c in configurations]
        ids = [[arm.position_id(q) for q in c] for c in confs]
        if not confs or ids[0] != [self.prob.start[p] for p in self.members] or \
                ids[-1] != [self.prob.target[p] for p in self.members]:
            return len(configurations)
        for k in range(len(confs) - 1):
            q0, q1 = confs[k], confs[k + 1]
            if np.any((q1 < 0) | (q1 >= steps)):
                return k
            delta = q1 - q0
            for j, w in enumerate(arm.wraps):
                if w:
                    delta[:, j] = (delta[:, j] + 1) % steps[j] - 1
            if np.any(np.abs(delta) > 1):
                return k
            for a, b, t in self.pairs:
                if not delta[a].any() and not delta[b].any():
                    continue  # the configuration itself: free as the end of the step before
                verdict = t.motion(q0[a][None], delta[a][None], q0[b][None], delta[b][None], None, None)
                if verdict[0] != FREE:
                    return k
        return None

    # -- breadth-first search ------------------------------------------------------------
    def _two_sided(self, succ, goal: bool, path: bool, label, bounds: bool = False):
        strict = self._bfs(succ, goal, path, False, label)
        if not strict.undecided:
            return (strict, strict) if bounds else strict
        loose = self._bfs(succ, goal, False, True, label)
        if bounds:
            return loose, strict
        if (loose.distance, loose.reachable if not goal else 0) != (strict.distance,
                                                                    strict.reachable if not goal else 0):
            raise OracleUndecided(f"members {self.members}: {strict.undecided} undecided swept entries read; "
                                  f"with them blocked {strict.distance} moves / {strict.reachable} reachable, "
                                  f"free {loose.distance} / {loose.reachable}")
        return strict

    def single_bounds(self) -> tuple[Outcome, Outcome]:
        """The single-move search with undecided entries free, then blocked: the true graph
        lies between the two (module docstring)."""
        return self.single(bounds=True)

    def _bfs(self, succ, goal: bool, path: bool, lenient: bool, label) -> Outcome:
        start = self.encode(self.prob.start)
        target = self.encode(self.prob.target) if goal else -1
        seen = np.zeros(self.total, dtype=bool)
        parent = np.full(self.total, -1, dtype=np.int64) if path else None
        how = np.full(self.total, -1, dtype=np.int32) if path else None
        seen[start] = True
        frontier = np.array([start], dtype=np.int64)
        depth, count, undecided = 0, 1, 0
        found = start == target
        while len(frontier) and not found:
            batches, und = succ(frontier, lenient)
            undecided += und
            fresh = []
            for nbr, src, code in batches:
                keep = ~seen[nbr]
                nbr, src = nbr[keep], src[keep]
                nbr, first = np.unique(nbr, return_index=True)
                seen[nbr] = True
                if path:
                    parent[nbr], how[nbr] = src[first], code
                fresh.append(nbr)
            frontier = np.concatenate(fresh) if fresh else np.zeros(0, dtype=np.int64)
            depth += 1
            count += len(frontier)
            found = goal and bool(seen[target])
        if goal and not found:
            return Outcome(None, count, None, undecided)
        moves = None
        if path and goal:
            moves, c = [], target
            while c != start:
                moves.append(label(int(how[c])))
                c = int(parent[c])
            moves.reverse()
        return Outcome(depth if goal else None, count, moves, undecided, None if goal else np.flatnonzero(seen))
