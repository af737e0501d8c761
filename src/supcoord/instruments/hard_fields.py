"""Hard fields on a real wok, seeded: offline robots in the way, targets drawn close together, unreachable targets.

kaiju's random targets (:func:`.wok.random_wok_targets`) are easy: every robot can reach its
own. Operations are not: robots go offline where they stand, targets crowd, and some targets
cannot be reached at all. :func:`hard_wok_field` makes such fields, the same for the same
seed, from the folded start; its kinds:

- ``"offline"``: ``count`` robots offline, each held with its arm stretched into its
  neighbours' patrol areas (the pose, among those clear of the folded neighbours and of the
  fiducials, that comes nearest to most neighbours' elbow circles); the other robots get
  kaiju-like random targets, clear of the offline arms;
- ``"close"``: ``count`` clusters, each a robot and its neighbours whose fibres are drawn, one
  after the other, inside a disc of radius :data:`CLOSE_RADIUS_MM` around the robot's alpha
  axis (a member with no clear place there is drawn like the others), so the targets lie in
  each other's paths; the other robots random;
- ``"unreachable"``: ``count`` robots each with a target that no motion reaches, because an
  offline neighbour's arm cuts the robot's joint space in two; the other robots random.

*Unreachable* is proved, not guessed (:func:`unreachable_certificate`): with every other
movable robot removed, the robot's start and target lie in different connected parts of its
free joint space, computed on a 1° grid of ``(α, β)`` with the obstacles shrunk by more than
the farthest any point of the arm moves between a configuration and its nearest grid node.
A continuous motion from start to target would pass through grid nodes that are free under
the shrunk obstacles and neighbours of each other (8-connected), so two parts that no chain
of such nodes joins cannot be joined by any motion. Every field is a valid problem: start
and target each collision-free under the instrument's definition (:mod:`.wok`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from ..errors import InputError
from ..geometry.segments import segment_distance
from .acceptance import collision_definition
from .sdss_v import FIDUCIAL_WATCH, InstrumentGeometry, fibre_joints, robot_forward
from .wok import TARGET_BETA_RANGE, _SAFETY_MM, _collided, _draw, _geometry, _neighbours, folded_configuration, wok_problem

__all__ = ["KINDS", "HardField", "UnreachableCertificate", "hard_wok_field", "unreachable_certificate"]

#: the kinds of :func:`hard_wok_field`
KINDS: tuple[str, ...] = ("offline", "close", "unreachable")
#: ``"close"``: the radius (mm) of a cluster's disc, around its centre robot's alpha axis
CLOSE_RADIUS_MM = 12.0
#: the certificate's grid step (degrees)
GRID_DEG = 1.0
#: candidate offline poses: alpha every 5°, beta every 5° up to 60° (the arm stretched out)
_POSE_ALPHA = np.arange(0.0, 360.0, 5.0)
_POSE_BETA = np.arange(0.0, 65.0, 5.0)


@dataclass(frozen=True)
class UnreachableCertificate:
    """Why robot ``robot`` cannot reach ``target`` from ``start`` (degrees), whatever the others do.

    ``blockers`` are the offline robots (row indices) whose arms, with the fixed obstacles,
    cut its free joint space; ``relax_mm`` how far the obstacles were shrunk (more than
    ``bound_mm``, the farthest an arm point moves to its nearest node of the ``grid_deg``
    grid); ``start_part`` and ``target_part`` the sizes (grid nodes) of the two parts.
    """

    robot: int
    start: tuple[float, float]
    target: tuple[float, float]
    blockers: tuple[int, ...]
    grid_deg: float
    bound_mm: float
    relax_mm: float
    start_part: int
    target_part: int


@dataclass(frozen=True)
class HardField:
    """A hard field: start and target ``(N, 2)`` in degrees (table row order), offline robots.

    ``offline`` maps a row to its held ``(α, β)`` (also its start and target rows);
    ``clusters`` the robots of each ``"close"`` cluster; ``certificates`` the robots whose
    targets are proved unreachable (:class:`UnreachableCertificate`), for every kind.
    """

    instrument: str
    kind: str
    seed: int
    start: np.ndarray = field(repr=False)
    target: np.ndarray = field(repr=False)
    offline: dict[int, tuple[float, float]]
    clusters: tuple[tuple[int, ...], ...] = ()
    certificates: tuple[UnreachableCertificate, ...] = ()

    @property
    def unreachable(self) -> tuple[int, ...]:
        """Rows whose targets are proved unreachable."""
        return tuple(c.robot for c in self.certificates)

    def problem(self, name: str | None = None) -> dict:
        """The field as a PROBLEM.json object (:func:`.wok.wok_problem` plus ``offline``)."""
        d = wok_problem(self.instrument, self.start, self.target,
                        name=name or f"{self.instrument}-{self.kind}-s{self.seed}",
                        description=f"hard_wok_field({self.instrument!r}, seed={self.seed}, kind={self.kind!r})")
        if self.offline:
            d["offline"] = {str(p): [float(a), float(b)] for p, (a, b) in sorted(self.offline.items())}
        return d


def _clearances(geom: InstrumentGeometry, p: int, seg: np.ndarray, others: np.ndarray, relax: float = 0.0):
    """Per pose of robot ``p`` (segments ``(K, 2, 2)``): is it clear of the segments ``others``
    ``(M, 2, 2)`` (other robots), the fixed obstacles and kaiju's fiducial rule? Clearances
    shrunk by ``relax`` mm (the rule is applied by the caller)."""
    rule = collision_definition(geom.name)
    ok = np.ones(len(seg), dtype=bool)
    if len(others):
        d = segment_distance(seg[:, None, 0], seg[:, None, 1], others[None, :, 0], others[None, :, 1])
        ok &= np.all(d >= 2 * rule.buffer_mm + rule.margin_mm + _SAFETY_MM - relax, axis=1)
    reach = float(geom.alpha_arm[p] + np.linalg.norm(geom.beta_segment[p], axis=1).max())
    near = np.linalg.norm(geom.obstacles[:, 0] - geom.bases[p], axis=1) < reach + rule.buffer_mm + 4.0
    if near.any():
        obs = geom.obstacles[near]
        d = segment_distance(seg[:, None, 0], seg[:, None, 1], obs[None, :, 0], obs[None, :, 1])
        need = rule.buffer_mm + geom.obstacle_buffers[near] + rule.obstacle_margin_mm + _SAFETY_MM - relax
        ok &= np.all(d >= need[None], axis=1)
    return ok


def _rule_ok(geom: InstrumentGeometry, p: int, alpha, beta, relax_deg: float = 0.0):
    """kaiju's fiducial rule for robot ``p`` (only robots beside a fiducial): ``β ≥ c0 + c1·α``."""
    if geom.fiducial_watch is None or not geom.fiducial_watch[p]:
        return np.ones(np.shape(alpha), dtype=bool)
    c0, c1 = FIDUCIAL_WATCH
    return np.asarray(beta) >= c0 + c1 * np.asarray(alpha) + 1e-9 - relax_deg


def _robot_pairs(pairs: np.ndarray, p: int) -> np.ndarray:
    """The neighbours of robot ``p``."""
    return np.concatenate([pairs[pairs[:, 0] == p, 1], pairs[pairs[:, 1] == p, 0]])


def _grid(geom: InstrumentGeometry, step: float):
    lo_a, hi_a = geom.alpha_range_deg
    lo_b, hi_b = geom.beta_range_deg
    return (np.linspace(lo_a, hi_a, int(round((hi_a - lo_a) / step)) + 1),
            np.linspace(lo_b, hi_b, int(round((hi_b - lo_b) / step)) + 1))


def _parts(geom: InstrumentGeometry, p: int, offline: dict[int, tuple[float, float]], step: float):
    """Robot ``p``'s free joint space on the grid, obstacles shrunk (module docstring): labels
    ``(A, B)`` (0 = blocked), the grid's alphas and betas, the bound and the relaxation (mm)."""
    alphas, betas = _grid(geom, step)
    reach = float(np.linalg.norm(geom.beta_segment[p], axis=1).max())
    bound = (float(geom.alpha_arm[p]) + 2 * reach) * math.radians(step) / 2
    relax = 1.25 * bound + 0.01
    a, b = (g.ravel() for g in np.meshgrid(alphas, betas, indexing="ij"))
    seg = robot_forward(geom, np.full(len(a), p), a, b)
    off = [q for q in offline if q != p]
    others = (robot_forward(geom, np.array(off), np.array([offline[q][0] for q in off]),
                            np.array([offline[q][1] for q in off])) if off else np.zeros((0, 2, 2)))
    c1 = FIDUCIAL_WATCH[1]
    free = _clearances(geom, p, seg, others, relax) & _rule_ok(geom, p, a, b, (1 + abs(c1)) * step / 2 + 0.01)
    labels, _ = ndimage.label(free.reshape(len(alphas), len(betas)), structure=np.ones((3, 3), dtype=int))
    return labels, alphas, betas, bound, relax


def _node(values: np.ndarray, x: float) -> int:
    return int(np.argmin(np.abs(values - x)))


def unreachable_certificate(instrument, robot: int, start, target, offline) -> UnreachableCertificate | None:
    """A proof that ``robot`` cannot go from ``start`` to ``target`` past the ``offline`` robots.

    Parameters
    ----------
    instrument : str or InstrumentGeometry
        ``"sdss-v-apo"``, ``"sdss-v-lco"`` or a loaded geometry.
    robot : int
        Row of the robot.
    start, target : pair of float
        Its ``(α, β)`` in degrees.
    offline : mapping
        Row -> ``(α, β)`` degrees of the robots held in place.

    Returns
    -------
    UnreachableCertificate or None
        The certificate (module docstring), or None when none is found (the target may or may
        not be reachable).

    Raises
    ------
    InputError
        An unknown instrument.

    Examples
    --------
    >>> f = hard_wok_field("sdss-v-apo", seed=0, kind="unreachable", count=1)
    >>> c = f.certificates[0]
    >>> unreachable_certificate("sdss-v-apo", c.robot, c.start, c.target, f.offline) == c
    True

    References
    ----------
    Configuration-space connectivity: T. Lozano-Pérez, "Spatial planning: a configuration space
    approach", IEEE Trans. Computers C-32 (1983); ``docs/instruments.md``.
    """
    geom = _geometry(instrument)
    labels, alphas, betas, bound, relax = _parts(geom, int(robot), dict(offline), GRID_DEG)
    s = labels[_node(alphas, start[0]), _node(betas, start[1])]
    t = labels[_node(alphas, target[0]), _node(betas, target[1])]
    if s == t or t == 0:
        return None
    sizes = np.bincount(labels.ravel())
    blockers = tuple(sorted(q for q in offline if q != robot))
    return UnreachableCertificate(int(robot), (float(start[0]), float(start[1])), (float(target[0]), float(target[1])),
                                  blockers, GRID_DEG, bound, relax, int(sizes[s]) if s else 0, int(sizes[t]))


def _unreachable_target(geom, p: int, start, offline, rng) -> tuple[float, float] | None:
    """A target of robot ``p`` outside the part of its free joint space holding ``start``, clear
    of the offline arms and obstacles (unshrunk), drawn by ``rng``; or None."""
    labels, alphas, betas, _, _ = _parts(geom, p, offline, GRID_DEG)
    s = labels[_node(alphas, start[0]), _node(betas, start[1])]
    cand = np.argwhere((labels != 0) & (labels != s) & (betas <= TARGET_BETA_RANGE[1])[None])
    if not len(cand):
        return None
    rng.shuffle(cand)
    off = sorted(offline)
    others = robot_forward(geom, np.array(off), np.array([offline[q][0] for q in off]),
                           np.array([offline[q][1] for q in off]))
    for i, j in cand[:200]:
        a, b = float(alphas[i]), float(betas[j])
        seg = robot_forward(geom, np.array([p]), np.array([a]), np.array([b]))
        if _clearances(geom, p, seg, others)[0] and _rule_ok(geom, p, a, b):
            return a, b
    return None


def _pose_others(geom, p: int, configs: list[np.ndarray], pairs: np.ndarray) -> np.ndarray:
    """The segments of ``p``'s neighbours in every configuration of ``configs`` (rows of NaN: not set)."""
    nb = _robot_pairs(pairs, p)
    out = []
    for conf in configs:
        q = nb[np.all(np.isfinite(conf[nb]), axis=1)]
        out.append(robot_forward(geom, q, conf[q, 0], conf[q, 1]))
    return np.concatenate(out) if out else np.zeros((0, 2, 2))


def _place_offline(geom, p: int, start: np.ndarray, target: np.ndarray, pairs, rng) -> tuple[float, float] | None:
    """Robot ``p``'s most obstructive pose (module docstring) clear of the neighbours' starts, of the
    targets already fixed, the obstacles and the fiducial rule, or None; ties drawn by ``rng``."""
    a, b = (g.ravel() for g in np.meshgrid(_POSE_ALPHA, _POSE_BETA))
    seg = robot_forward(geom, np.full(len(a), p), a, b)
    nb = _robot_pairs(pairs, p)
    ok = _clearances(geom, p, seg, _pose_others(geom, p, [start, target], pairs)) & _rule_ok(geom, p, a, b)
    if not ok.any():
        return None
    d_base = segment_distance(seg[:, None, 0], seg[:, None, 1], geom.bases[nb][None], geom.bases[nb][None])
    score = np.sum(d_base < geom.alpha_arm[nb][None] + 2 * geom.robot_buffer, axis=1) + rng.uniform(0, 0.5, len(a))
    score[~ok] = -1.0
    k = int(np.argmax(score))
    return float(a[k]), float(b[k])


def _fill(geom, target: np.ndarray, pairs: np.ndarray, rng, max_rounds: int = 1000) -> None:
    """kaiju-like random targets (:func:`.wok.random_wok_targets`) for the rows of ``target`` that
    are NaN, the set rows held: drawn, then every colliding free robot drawn again."""
    free = ~np.all(np.isfinite(target), axis=1)
    target[free] = _draw(geom, np.flatnonzero(free), "metrology", rng)
    for _ in range(max_rounds):
        hit = _collided(geom, target, pairs)
        if not hit.any():
            return
        redo = hit & free
        if not redo.any():
            raise InputError(f"robots {np.flatnonzero(hit)[:5].tolist()} collide among the fixed targets",
                             value=np.flatnonzero(hit)[:5].tolist())
        target[redo] = _draw(geom, np.flatnonzero(redo), "metrology", rng)
    raise InputError(f"no collision-free targets after {max_rounds} rounds", value=max_rounds)


def _cluster_member(geom, p: int, centre: int, target: np.ndarray, pairs, rng) -> tuple[float, float] | None:
    """A target of ``p`` with its metrology fibre in the disc of ``centre`` (``CLOSE_RADIUS_MM``),
    clear of the set targets and the obstacles; None after 400 draws."""
    r = CLOSE_RADIUS_MM * np.sqrt(rng.uniform(0, 1, 400))
    t = rng.uniform(0, 2 * np.pi, 400)
    xy = geom.bases[centre] + np.stack([r * np.cos(t), r * np.sin(t)], 1)
    ab = fibre_joints(geom, np.full(len(xy), p), xy, "metrology")
    lo, hi = TARGET_BETA_RANGE
    ab = ab[np.all(np.isfinite(ab), axis=1) & (ab[:, 1] >= lo) & (ab[:, 1] <= hi)]
    if not len(ab):
        return None
    seg = robot_forward(geom, np.full(len(ab), p), ab[:, 0], ab[:, 1])
    ok = _clearances(geom, p, seg, _pose_others(geom, p, [target], pairs)) & _rule_ok(geom, p, ab[:, 0], ab[:, 1])
    k = np.flatnonzero(ok)
    return (float(ab[k[0], 0]), float(ab[k[0], 1])) if len(k) else None


def _check_args(kind, seed, count) -> None:
    if kind not in KINDS:
        raise InputError(f"kind must be one of {', '.join(KINDS)}, got {kind!r:.40}", value=kind)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2 ** 63:
        raise InputError(f"seed must be an integer in [0, 2**63), got {seed!r:.40}", value=seed)
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not 1 <= count <= 50:
        raise InputError(f"count must be an integer in [1, 50], got {count!r:.40}", value=count)


def hard_wok_field(instrument: str | InstrumentGeometry = "sdss-v-apo", seed: int = 0, kind: str = "offline", *,
                   count: int = 3) -> HardField:
    """A hard field on a real wok (module docstring), the same for the same arguments.

    Parameters
    ----------
    instrument : str or InstrumentGeometry
        ``"sdss-v-apo"``, ``"sdss-v-lco"`` or a loaded geometry.
    seed : int
        Seed of the random generator (an integer >= 0); each kind draws its own stream.
    kind : str
        ``"offline"``, ``"close"`` or ``"unreachable"``.
    count : int
        Offline robots, clusters, or proved-unreachable targets (1 to 50).

    Returns
    -------
    HardField
        Start (folded, offline robots where they are held) and target ``(N, 2)`` in degrees, the
        offline robots, the clusters and the unreachable targets' certificates.

    Raises
    ------
    InputError
        An unknown instrument or kind, a bad seed or count, or no field found (e.g. fewer
        unreachable targets than ``count`` after trying every robot).

    Examples
    --------
    >>> f = hard_wok_field("sdss-v-apo", seed=1, kind="close", count=2)
    >>> len(f.clusters), f.start.shape, f.problem()["layout"]["name"]
    (2, (500, 2), 'sdss-v-apo')
    >>> bool(np.array_equal(f.target, hard_wok_field("sdss-v-apo", seed=1, kind="close", count=2).target))
    True

    References
    ----------
    Offline robots and deadlocks in operation: jaeger (``sdss/jaeger``) ``_resolve_deadlocks``;
    kaiju's random targets: ``getRandomPathPair``; ``docs/instruments.md``.
    """
    _check_args(kind, seed, count)
    geom = _geometry(instrument)
    rng = np.random.default_rng((int(seed), KINDS.index(kind)))
    pairs = _neighbours(geom)
    n = len(geom.hole_ids)
    start = folded_configuration(geom)
    target = np.full((n, 2), np.nan)
    offline: dict[int, tuple[float, float]] = {}
    clusters: list[tuple[int, ...]] = []
    certs: list[int] = []
    used = np.zeros(n, dtype=bool)
    for p in rng.permutation(n).tolist():
        if len(offline if kind == "offline" else clusters if kind == "close" else certs) >= count:
            break
        if used[p]:
            continue
        if kind == "close":
            clusters.append(_cluster(geom, p, target, pairs, used, rng))
        else:
            _block(geom, p, kind, start, target, offline, certs, pairs, used, rng)
    got = len(offline if kind == "offline" else clusters if kind == "close" else certs)
    if got < count:
        raise InputError(f"only {got} of {count} {kind} robots found on {geom.name}", value=got)
    _fill(geom, target, pairs, rng)
    found = _certify(geom, start, target, offline, pairs)
    lost = set(certs) - {c.robot for c in found}
    if lost:  # more offline arms only cut the joint space further: never expected
        raise InputError(f"robots {sorted(lost)} lost their unreachability certificates", value=sorted(lost))
    return HardField(geom.name, kind, int(seed), start, target, offline, tuple(clusters), tuple(found))


def _cluster(geom, c: int, target, pairs, used, rng) -> tuple[int, ...]:
    """The ``"close"`` cluster around robot ``c``: targets set in place; its members."""
    nb = _robot_pairs(pairs, c)
    members = [c] + [int(q) for q in nb if np.linalg.norm(geom.bases[q] - geom.bases[c]) < 1.2 * 22.4]
    placed = []
    for q in rng.permutation(members).tolist():
        if used[q]:
            continue
        ab = _cluster_member(geom, q, c, target, pairs, rng)
        if ab is not None:
            target[q] = ab
            placed.append(q)
    used[members] = True
    used[_robot_pairs(pairs, c)] = True
    return tuple(sorted(placed))


def _block(geom, b: int, kind: str, start, target, offline, certs, pairs, used, rng) -> None:
    """Robot ``b`` offline in its most obstructive pose; for ``"unreachable"``, only when a
    neighbour then gets a target it provably cannot reach (set in place, certificate kept)."""
    if geom.fiducial_watch is not None and geom.fiducial_watch[b]:
        return
    pose = _place_offline(geom, b, start, target, pairs, rng)
    if pose is None:
        return
    if kind == "unreachable":
        trial = {**offline, b: pose}
        for a in rng.permutation(_robot_pairs(pairs, b)).tolist():
            if used[a] or not _deep(geom, b, pose, a):
                continue
            ab = _unreachable_target(geom, a, start[a], trial, rng)
            if ab is not None:
                target[a] = ab
                certs.append(a)
                used[a] = True
                break
        else:
            return
    offline[b] = pose
    start[b] = target[b] = pose
    used[b] = True
    used[_robot_pairs(pairs, b)] |= kind == "offline"


def _deep(geom, b: int, pose, a: int) -> bool:
    """Does ``b``'s arm at ``pose`` come within the buffers of ``a``'s elbow circle (plus 1 mm)?"""
    seg = robot_forward(geom, b, *pose)
    return float(segment_distance(seg[0], seg[1], geom.bases[a], geom.bases[a])) <= \
        geom.alpha_arm[a] + 2 * geom.robot_buffer + 1.0


def _certify(geom, start, target, offline, pairs) -> list[UnreachableCertificate]:
    """Certificates of the robots whose targets the offline arms make unreachable, looked for
    among the neighbours into whose elbow circle an offline arm reaches (:func:`_deep`)."""
    out = []
    near = {int(a) for b in offline for a in _robot_pairs(pairs, b) if _deep(geom, b, offline[b], int(a))}
    for q in sorted(near - set(offline)):
        c = unreachable_certificate(geom, q, start[q], target[q], offline)
        if c is not None:
            out.append(c)
    return out
